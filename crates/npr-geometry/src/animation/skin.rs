//! Skins: the joints and inverse bind matrices, and the linear blend of joint matrices
//! (glTF 2.0, §3.7.3 Skins).

use glam::{Mat3, Mat4, Vec3};

/// A skin (glTF 2.0, §3.7.3): the nodes that act as its joints and, per joint, the
/// inverse bind matrix that takes a bind-space vertex into the joint's space (the
/// identity when the file gives none).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skin {
    /// The skin's name in the file, if any.
    pub name: Option<String>,
    /// Joint `j` is node `joints[j]` of [`super::Rig::nodes`].
    pub joints: Vec<usize>,
    /// One inverse bind matrix per joint.
    pub inverse_bind: Vec<Mat4>,
}

/// The linear blend `Σ wᵢ Mᵢ` of the joint matrices a vertex uses; joint indices past
/// `joint_matrices` count as the identity (a rig built by [`super::Rig`]'s loaders never
/// has any).
pub(crate) fn blend(influences: &[(u16, f32)], joint_matrices: &[Mat4]) -> Mat4 {
    let mut m = Mat4::ZERO;
    for &(j, w) in influences {
        let jm = joint_matrices
            .get(usize::from(j))
            .copied()
            .unwrap_or(Mat4::IDENTITY);
        m += jm * w;
    }
    m
}

/// The matrix that carries normals under `m`: the inverse-transpose of its linear part,
/// computed as the cofactor matrix times the determinant's sign, so a singular blend
/// (a joint scaled to zero) still gives a direction instead of NaN.
pub(crate) fn normal_matrix(m: Mat4) -> Mat3 {
    let a = Mat3::from_mat4(m);
    let (x, y, z) = (a.x_axis, a.y_axis, a.z_axis);
    let cof = Mat3::from_cols(y.cross(z), z.cross(x), x.cross(y));
    if a.determinant() < 0.0 { -cof } else { cof }
}

/// `n` carried by `m` and normalised; `Vec3::Z` when it vanishes.
pub(crate) fn transform_normal(m: Mat4, n: Vec3) -> Vec3 {
    (normal_matrix(m) * n).try_normalize().unwrap_or(Vec3::Z)
}
