//! glTF 2.0 (`.gltf` JSON with external or data-URI buffers, `.glb`): every triangle
//! primitive of the default scene (or the first scene), node transforms applied, merged
//! into one mesh.
//!
//! The `gltf` crate provides the validated document; the GLB container, the buffers and
//! the accessors are read here with checked byte ranges, so a truncated or inconsistent
//! file is a [`LoadError`] naming the byte, buffer or accessor, never a panic.

use std::path::Path;

use glam::Mat4;

use super::{LoadError, Raw};

mod buffers;
mod primitive;
pub(crate) mod rig;

use buffers::{GLB_MAGIC, load_buffers, split_glb};
use primitive::Merged;

/// Extensions that do not change geometry: required or not, the mesh reads the same.
fn geometry_neutral(ext: &str) -> bool {
    ext.starts_with("KHR_materials_")
        || ext.starts_with("KHR_texture_")
        || ext.starts_with("EXT_texture_")
        || ext == "KHR_lights_punctual"
}

struct Ctx<'a> {
    file: &'a str,
}

impl Ctx<'_> {
    fn parse(&self, at: impl Into<String>, reason: impl Into<String>) -> LoadError {
        LoadError::Parse {
            file: self.file.to_string(),
            at: at.into(),
            reason: reason.into(),
        }
    }
    fn truncated(&self, at: impl Into<String>, reason: impl Into<String>) -> LoadError {
        LoadError::Truncated {
            file: self.file.to_string(),
            at: at.into(),
            reason: reason.into(),
        }
    }
}

/// The merged mesh, and the rig parts when the file has a skin, a morph target or an
/// animation.
pub(crate) fn parse(
    bytes: &[u8],
    file: &str,
    dir: Option<&Path>,
) -> Result<(Raw, Option<rig::RigParts>), LoadError> {
    let c = Ctx { file };
    let (json, bin) = if bytes.starts_with(GLB_MAGIC) {
        split_glb(bytes, &c)?
    } else {
        (bytes, None)
    };
    let doc = read_document(json, &c)?;
    let buffers = load_buffers(&doc, bin, dir, &c)?;
    let instances = mesh_instances(&doc, &c)?;
    let animated = rig::has_animation(&doc);
    let mut merged = Merged::new(animated);
    for (mesh, node, world) in &instances {
        merged.instance(mesh, node.as_ref(), *world, &buffers, &c)?;
    }
    let (raw, parts) = merged.into_raw(instances.len());
    let parts = match parts {
        Some((insts, verts)) => Some(rig::read(&doc, &buffers, insts, verts, &c)?),
        None => None,
    };
    Ok((raw, parts))
}

/// Parses and validates the JSON document, refusing extensions that change geometry.
fn read_document(json: &[u8], c: &Ctx<'_>) -> Result<gltf::Document, LoadError> {
    let root = gltf::json::Root::from_slice(json).map_err(|e| {
        c.parse(
            format!("JSON line {} column {}", e.line(), e.column()),
            super::error::one_line(&e.to_string()),
        )
    })?;
    if let Some(ext) = root
        .extensions_required
        .iter()
        .find(|e| !geometry_neutral(e))
    {
        return Err(LoadError::UnsupportedExtension {
            file: c.file.to_string(),
            extension: ext.clone(),
        });
    }
    // `gltf-json`'s validation indexes the POSITION accessor unchecked: check primitive
    // accessor indices first.
    check_primitive_accessors(&root, c)?;
    // Nor does it check animation channel targets, which `gltf` then unwraps.
    check_channel_targets(&root, c)?;
    validate(root, c)
}

/// Checks that every accessor a primitive refers to exists.
fn check_primitive_accessors(root: &gltf::json::Root, c: &Ctx<'_>) -> Result<(), LoadError> {
    let n_acc = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let bad = prim
                .attributes
                .values()
                .chain(prim.indices.iter())
                .map(|i| i.value())
                .find(|&i| i >= n_acc);
            if let Some(i) = bad {
                return Err(c.parse(
                    format!("meshes[{m}].primitives[{p}]"),
                    format!("accessor {i} does not exist ({n_acc} accessors)"),
                ));
            }
        }
    }
    Ok(())
}

/// Checks that every animation channel targets a node that exists, with a known path.
fn check_channel_targets(root: &gltf::json::Root, c: &Ctx<'_>) -> Result<(), LoadError> {
    let n_nodes = root.nodes.len();
    for (a, anim) in root.animations.iter().enumerate() {
        for (k, ch) in anim.channels.iter().enumerate() {
            let at = format!("animations[{a}].channels[{k}].target");
            let node = ch.target.node.value();
            if node >= n_nodes {
                return Err(c.parse(at, format!("node {node} does not exist ({n_nodes} nodes)")));
            }
            if matches!(ch.target.path, gltf::json::validation::Checked::Invalid) {
                return Err(c.parse(at, "unknown target path"));
            }
        }
    }
    Ok(())
}

/// Validates the document, tolerating only missing POSITION `min`/`max`.
fn validate(root: gltf::json::Root, c: &Ctx<'_>) -> Result<gltf::Document, LoadError> {
    // `min`/`max`: required by the spec, left out by some exporters, never read here.
    match gltf::Document::from_json(root.clone()) {
        Ok(doc) => Ok(doc),
        Err(gltf::Error::Validation(errs)) => {
            let serious: Vec<_> = errs
                .iter()
                .filter(|(p, _)| {
                    let p = p.to_string();
                    !(p.ends_with(".min") || p.ends_with(".max"))
                })
                .collect();
            match serious.first() {
                None => Ok(gltf::Document::from_json_without_validation(root)),
                Some((path, err)) => Err(c.parse(
                    path.to_string(),
                    format!("invalid glTF: {err} ({} problem(s) in all)", serious.len()),
                )),
            }
        }
        Err(e) => Err(c.parse("document", super::error::one_line(&e.to_string()))),
    }
}

/// A mesh, the node that instances it (none without a scene) and its world matrix.
type MeshInstance<'d> = (gltf::Mesh<'d>, Option<gltf::Node<'d>>, Mat4);

/// Mesh instances from the default (or first) scene's graph.
fn mesh_instances<'d>(
    doc: &'d gltf::Document,
    c: &Ctx<'_>,
) -> Result<Vec<MeshInstance<'d>>, LoadError> {
    // Iteratively, with a step bound so a cyclic graph cannot loop; without a scene,
    // every mesh untransformed.
    let mut instances: Vec<MeshInstance<'d>> = Vec::new();
    match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => {
            let mut stack: Vec<(gltf::Node<'_>, Mat4)> =
                scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
            stack.reverse();
            let mut steps = 0usize;
            let limit = doc.nodes().len().max(1) * 64;
            while let Some((node, parent)) = stack.pop() {
                steps += 1;
                if steps > limit {
                    return Err(c.parse("nodes", "the node hierarchy has a cycle"));
                }
                let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
                if let Some(mesh) = node.mesh() {
                    instances.push((mesh, Some(node.clone()), world));
                }
                // Reversed: nodes pop in document order, depth first.
                let at = stack.len();
                stack.extend(node.children().map(|n| (n, world)));
                stack[at..].reverse();
            }
        }
        None => instances.extend(doc.meshes().map(|m| (m, None, Mat4::IDENTITY))),
    }
    Ok(instances)
}
