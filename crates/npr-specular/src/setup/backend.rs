//! Where a mesh's highlights are set up: the [`Backend`], chosen once per mesh before its
//! first frame by [`Backend::choose`], and why ([`BackendChoice`]).
//!
//! The rule, in order:
//! 1. a setting other than [`BackendSetting::Auto`] decides;
//! 2. a software adapter ([`wgpu::DeviceType::Cpu`]: llvmpipe, lavapipe, SwiftShader, WARP)
//!    gives [`Backend::Cpu`]: its compute runs on the cores the CPU backend would use, and
//!    the whole frame measured 2.3–6.8× the CPU backend's there (`docs/setup.md`);
//! 3. an adapter that does not say what it is ([`wgpu::DeviceType::Other`], as browsers
//!    report) gives [`Backend::Cpu`], the backend that is never slower than a software
//!    adapter's GPU frame;
//! 4. a real GPU (discrete, integrated or virtual) gives [`Backend::Gpu`];
//! 5. whatever 1–4 gave, [`Backend::Gpu`] falls back to [`Backend::Cpu`] where the mesh's
//!    tables exceed the device's storage bindings
//!    ([`crate::HighlightSetup::create_object`] decides that, once, when it sizes them).

use std::fmt;

/// The two ways a frame's highlights are set up. Both give the same highlights (the tests
/// loop over [`Backend::ALL`]); they differ in where the work runs and what it costs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// [`crate::HighlightSet::update`] on the CPU: the `N = H` search, matching, regions,
    /// projectors and §4.2 receivers, then an upload of the frame's projectors and
    /// receiver list.
    Cpu,
    /// The whole frame recorded into the caller's encoder as compute passes (search,
    /// regions, projectors, receivers, and a moving model's pose), drawn where it lies;
    /// nothing is read back on the frame's path. The CPU sees each frame's highlights one
    /// frame late, for picking and panels.
    Gpu,
}

impl Backend {
    /// Both backends, for tests and benches that compare them.
    pub const ALL: [Backend; 2] = [Backend::Cpu, Backend::Gpu];

    /// The backend's name as settings and benches write it (`"cpu"`, `"gpu"`).
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
        }
    }

    /// Applies the rule of the module docs (steps 1–4) to an adapter; step 5 is
    /// [`crate::HighlightSetup::create_object`]'s.
    pub fn choose(adapter: &wgpu::AdapterInfo, setting: BackendSetting) -> BackendChoice {
        let (backend, reason) = match setting {
            BackendSetting::Cpu => (Backend::Cpu, ChoiceReason::Setting),
            BackendSetting::Gpu => (Backend::Gpu, ChoiceReason::Setting),
            BackendSetting::Auto => match adapter.device_type {
                wgpu::DeviceType::Cpu => (Backend::Cpu, ChoiceReason::SoftwareAdapter),
                wgpu::DeviceType::Other => (Backend::Cpu, ChoiceReason::UnknownAdapter),
                wgpu::DeviceType::DiscreteGpu
                | wgpu::DeviceType::IntegratedGpu
                | wgpu::DeviceType::VirtualGpu => (Backend::Gpu, ChoiceReason::HardwareAdapter),
            },
        };
        BackendChoice {
            backend,
            reason,
            adapter: adapter.name.clone(),
        }
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An adapter that says nothing of itself ([`wgpu::DeviceType::Other`], no name), for a
/// caller that does not know the adapter its device came from: the rule gives it the CPU.
pub fn unknown_adapter() -> wgpu::AdapterInfo {
    wgpu::AdapterInfo {
        name: String::new(),
        vendor: 0,
        device: 0,
        device_type: wgpu::DeviceType::Other,
        device_pci_bus_id: String::new(),
        driver: String::new(),
        driver_info: String::new(),
        backend: wgpu::Backend::Noop,
        subgroup_min_size: 0,
        subgroup_max_size: 0,
        transient_saves_memory: None,
        limit_bucket: None,
    }
}

/// What the caller asks for: [`BackendSetting::Auto`] (the rule) or one backend.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BackendSetting {
    /// [`Backend::choose`]'s rule.
    #[default]
    Auto,
    /// Always [`Backend::Cpu`].
    Cpu,
    /// [`Backend::Gpu`] wherever the mesh's tables fit the device.
    Gpu,
}

/// Why a backend was chosen.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ChoiceReason {
    /// The caller's [`BackendSetting`].
    Setting,
    /// `Auto` on a software adapter (rule 2).
    SoftwareAdapter,
    /// `Auto` on an adapter of unknown type (rule 3).
    UnknownAdapter,
    /// `Auto` on a real GPU (rule 4).
    HardwareAdapter,
    /// The GPU frame's tables exceed the device's limits (rule 5); the error's line.
    MeshTooLarge(String),
}

/// The backend a mesh's setup runs, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BackendChoice {
    /// The backend.
    pub backend: Backend,
    /// Why.
    pub reason: ChoiceReason,
    /// The adapter's name, for the reason's line.
    pub adapter: String,
}

impl BackendChoice {
    /// This choice moved to the CPU because the mesh's GPU tables do not fit (`why`: the
    /// error's line).
    pub(crate) fn too_large(&self, why: String) -> Self {
        Self {
            backend: Backend::Cpu,
            reason: ChoiceReason::MeshTooLarge(why),
            adapter: self.adapter.clone(),
        }
    }

    /// The reason as a short phrase (`"the setting"`, `"software adapter llvmpipe"`, ...).
    pub fn why(&self) -> String {
        match &self.reason {
            ChoiceReason::Setting => "the setting".into(),
            ChoiceReason::SoftwareAdapter => format!("software adapter {}", self.adapter),
            ChoiceReason::UnknownAdapter => format!("adapter of unknown type {}", self.adapter),
            ChoiceReason::HardwareAdapter => format!("GPU {}", self.adapter),
            ChoiceReason::MeshTooLarge(why) => format!("the GPU frame does not fit: {why}"),
        }
    }
}

impl fmt::Display for BackendChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.backend, self.why())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adapter(device_type: wgpu::DeviceType) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: "test adapter".into(),
            device_type,
            ..unknown_adapter()
        }
    }

    #[test]
    fn auto_gives_the_gpu_frame_only_on_a_real_gpu() {
        use wgpu::DeviceType as T;
        let cases = [
            (T::Cpu, Backend::Cpu, ChoiceReason::SoftwareAdapter),
            (T::Other, Backend::Cpu, ChoiceReason::UnknownAdapter),
            (T::DiscreteGpu, Backend::Gpu, ChoiceReason::HardwareAdapter),
            (
                T::IntegratedGpu,
                Backend::Gpu,
                ChoiceReason::HardwareAdapter,
            ),
            (T::VirtualGpu, Backend::Gpu, ChoiceReason::HardwareAdapter),
        ];
        for (device_type, backend, reason) in cases {
            let c = Backend::choose(&adapter(device_type), BackendSetting::Auto);
            assert_eq!((c.backend, c.reason), (backend, reason), "{device_type:?}");
        }
    }

    #[test]
    fn a_setting_overrides_the_rule_on_every_adapter() {
        use wgpu::DeviceType as T;
        for device_type in [T::Cpu, T::Other, T::DiscreteGpu, T::IntegratedGpu] {
            for (setting, backend) in [
                (BackendSetting::Cpu, Backend::Cpu),
                (BackendSetting::Gpu, Backend::Gpu),
            ] {
                let c = Backend::choose(&adapter(device_type), setting);
                assert_eq!(c.backend, backend);
                assert_eq!(c.reason, ChoiceReason::Setting);
            }
        }
    }

    #[test]
    fn a_choice_says_its_backend_and_why_in_one_line() {
        let c = Backend::choose(&adapter(wgpu::DeviceType::Cpu), BackendSetting::Auto);
        assert_eq!(c.to_string(), "cpu (software adapter test adapter)");
        let big = Backend::choose(&adapter(wgpu::DeviceType::DiscreteGpu), Default::default())
            .too_large("mesh receiver work buffer needs 8 bytes".into());
        assert_eq!(big.backend, Backend::Cpu);
        assert!(
            big.to_string()
                .starts_with("cpu (the GPU frame does not fit: mesh")
        );
        assert!(!big.to_string().contains('\n'));
    }
}
