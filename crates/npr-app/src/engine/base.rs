//! The base shading (Phong, Gouraud, cel) of the engine: one [`BaseShading`] pass and its
//! object, specialised by a [`BaseKey`].

use npr_gpu::{BaseObject, BaseSettings, BaseShading, GpuMesh, TargetFormats};

/// What a base-shading pass is built for: the targets it draws into (sample count
/// included) and the grey levels of its cel ramp (darkest first; none: npr-gpu's default
/// ramp). The ramp is a setting, uploaded once when the pass is built.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct BaseKey {
    pub formats: TargetFormats,
    pub cel_bands: Vec<u8>,
}

/// A base-shading pass and the model's object in it.
pub(crate) struct BaseEffect {
    pub pass: BaseShading,
    pub object: BaseObject,
}

impl BaseEffect {
    /// The pass for `key`, drawing `mesh`.
    pub(crate) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GpuMesh,
        key: &BaseKey,
    ) -> Self {
        let pass = BaseShading::new(device, queue, key.formats, &ramp_settings(&key.cel_bands));
        let object = pass.create_object(device, mesh);
        Self { pass, object }
    }
}

/// The base shading settings of a cel ramp of `bands` (grey levels, darkest first; none:
/// npr-gpu's default ramp).
pub(crate) fn ramp_settings(bands: &[u8]) -> BaseSettings {
    if bands.is_empty() {
        return BaseSettings::default();
    }
    BaseSettings {
        ramp: npr_gpu::toon_ramp(256, &grey_shades(bands)),
    }
}

/// Opaque grey RGBA shades of `bands`.
pub(crate) fn grey_shades(bands: &[u8]) -> Vec<[u8; 4]> {
    bands.iter().map(|&g| [g, g, g, 255]).collect()
}
