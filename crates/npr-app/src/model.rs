//! A user's model: loaded with `npr-geometry`'s loaders, framed, with what the loader
//! changed or dropped kept for display.

use crate::AppError;
use crate::view::Framing;
use npr_geometry::Mesh;
use std::path::{Path, PathBuf};

/// The built-in model of `npr view` with no argument: the Stanford bunny (compiled in, so
/// the binary works from any directory). `assets/stanford-bunny.obj` links to the copy in
/// the repository's `fixtures/meshes/`; `cargo package` stores the file itself, so the
/// crate's package carries its model.
const BUNNY_OBJ: &str = include_str!("../assets/stanford-bunny.obj");

/// A loaded model.
#[derive(Clone, Debug)]
pub struct Model {
    /// Display name (the file name).
    pub name: String,
    /// The file it came from (`None` for built-ins).
    pub path: Option<PathBuf>,
    /// The mesh, in the file's own units.
    pub mesh: Mesh,
    /// What the loader dropped or changed, one line each.
    pub notes: Vec<String>,
    /// Its bounding sphere.
    pub framing: Framing,
    /// Its skins, morph targets and clips (glTF), tied to the file's vertices; the mesh
    /// above is the loaded one ([`crate::animation::Animated`] poses it).
    pub rig: Option<npr_geometry::animation::Rig>,
}

impl Model {
    /// A model from a mesh in memory, its triangles and vertices reordered for locality
    /// ([`npr_geometry::locality`]: the same triangles with the same corners and winding,
    /// vertices no triangle uses dropped; the highlight setup's face walks and the GPU's
    /// vertex cache both run faster on it).
    pub fn from_mesh(name: &str, mesh: Mesh) -> Self {
        Self::in_order(
            name,
            npr_geometry::locality::reorder_for_locality(&mesh).mesh,
        )
    }

    /// A model of `mesh` as it is, already in the order [`Model::from_mesh`] gives (a
    /// new pose of a rigged model, reordered once for all its poses).
    pub(crate) fn in_order(name: &str, mesh: Mesh) -> Self {
        let framing = Framing::of(&mesh);
        Self {
            name: name.to_string(),
            path: None,
            mesh,
            notes: Vec::new(),
            framing,
            rig: None,
        }
    }

    /// Loads an OBJ, PLY or glTF file.
    ///
    /// # Errors
    /// [`AppError::Load`] with the loader's one-line reason.
    pub fn load(path: &Path) -> Result<Self, AppError> {
        let loaded = npr_geometry::io::load(path).map_err(|source| AppError::Load {
            path: path.to_path_buf(),
            source,
        })?;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| path.display().to_string());
        let mut model = Self::from_mesh(&name, loaded.mesh);
        model.rig = loaded.rig;
        model.path = Some(path.to_path_buf());
        model.notes = loaded.report.iter().map(ToString::to_string).collect();
        Ok(model)
    }

    /// A model from a file's bytes (what a browser's file picker or drop hands over):
    /// `name` is the file name, whose extension gives the format.
    ///
    /// # Errors
    /// [`AppError::Load`] with the loader's one-line reason (an unknown extension too).
    pub fn from_bytes(name: &str, bytes: &[u8]) -> Result<Self, AppError> {
        let load_error = |source| AppError::Load {
            path: name.into(),
            source,
        };
        let ext = Path::new(name)
            .extension()
            .map(|e| e.to_string_lossy().into_owned())
            .unwrap_or_default();
        let format = npr_geometry::io::Format::from_extension(&ext).ok_or_else(|| {
            load_error(npr_geometry::io::LoadError::UnsupportedFormat {
                file: name.to_string(),
                extension: ext.clone(),
            })
        })?;
        let loaded = npr_geometry::io::load_bytes_named(bytes, format, name).map_err(load_error)?;
        let mut model = Self::from_mesh(name, loaded.mesh);
        model.rig = loaded.rig;
        model.notes = loaded.report.iter().map(ToString::to_string).collect();
        Ok(model)
    }

    /// The built-in bunny.
    ///
    /// # Errors
    /// [`AppError::Load`] if the embedded file does not parse (it always does).
    pub fn bunny() -> Result<Self, AppError> {
        let mut bunny = Self::from_bytes("stanford-bunny.obj", BUNNY_OBJ.as_bytes())?;
        // What the loader did to the built-in file is no news to the user.
        bunny.notes.clear();
        Ok(bunny)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dropped file's error is one line that names the file as its user knows it (not
    /// `<bytes>.ply`) and says what is wrong without the parser's internals.
    #[test]
    fn a_broken_dropped_file_is_named_in_its_error() {
        let Err(e) = Model::from_bytes("broken.ply", b"ply\nc") else {
            panic!("a broken PLY loaded");
        };
        let said = e.to_string();
        assert!(said.starts_with("broken.ply: header line 2: "), "{said}");
        assert!(
            !said.contains("ParseError") && !said.contains('\n'),
            "{said}"
        );
        let Err(e) = Model::from_bytes("scan.stl", b"solid") else {
            panic!("an STL loaded");
        };
        assert!(
            e.to_string().starts_with("scan.stl: unsupported format"),
            "{e}"
        );
    }
}
