//! How far one curvature field is from another on the same mesh (a GPU field against the
//! CPU reference, say): the measures the GPU curvature tests and the browser's compute
//! check bound.

use glam::Vec3;

use super::CurvatureField;

/// The worst differences of a field against a reference ([`CurvatureField::difference`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FieldDifference {
    /// Largest principal-curvature difference over the reference's robust largest |κ|
    /// (the 99th percentile of `max(|κ_max|, |κ_min|)` over valid vertices: smaller than
    /// the true largest, so a bound on it is stricter).
    pub kappa: f32,
    /// Largest normal angle, degrees.
    pub normal_deg: f32,
    /// Largest principal-direction angle (up to sign) where the reference's principal
    /// curvatures differ (`|κ_max − κ_min|` over 10 % of the larger magnitude), degrees.
    pub direction_deg: f32,
    /// Vertices whose validity differs.
    pub validity: usize,
    /// Vertices where the directions were compared.
    pub directions_checked: usize,
    /// Vertices compared.
    pub vertices: usize,
    /// The reference's robust largest |κ| and its true largest.
    pub scale: (f32, f32),
}

/// The angle between `a` and `b` in degrees, by `atan2(|a × b|, a · b)` in f64 (an f32
/// `acos` cannot tell angles below 0.02° apart), up to sign when asked.
fn angle(a: Vec3, b: Vec3, up_to_sign: bool) -> f32 {
    let (a, b) = (a.as_dvec3(), b.as_dvec3());
    let mut c = a.dot(b);
    if up_to_sign {
        c = c.abs();
    }
    a.cross(b).length().atan2(c).to_degrees() as f32
}

impl CurvatureField {
    /// How far `other` is from this field, vertex by vertex (see [`FieldDifference`]).
    /// Vertices past the shorter field are not compared; `vertices` says how many were.
    pub fn difference(&self, other: &CurvatureField) -> FieldDifference {
        let n = self.len().min(other.len());
        let mut mags: Vec<f32> = (0..n)
            .filter(|&v| self.valid[v])
            .map(|v| self.kappa_max[v].abs().max(self.kappa_min[v].abs()))
            .collect();
        mags.sort_by(f32::total_cmp);
        let robust = mags
            .get(((mags.len() as f32 * 0.99) as usize).min(mags.len().saturating_sub(1)))
            .copied()
            .unwrap_or(0.0);
        let mut e = FieldDifference {
            scale: (robust, mags.last().copied().unwrap_or(0.0)),
            vertices: n,
            ..FieldDifference::default()
        };
        let scale = robust.max(f32::MIN_POSITIVE);
        for v in 0..n {
            e.normal_deg = e
                .normal_deg
                .max(angle(self.normal[v], other.normal[v], false));
            if self.valid[v] != other.valid[v] {
                e.validity += 1;
                continue;
            }
            if !self.valid[v] {
                continue;
            }
            let dk = (self.kappa_max[v] - other.kappa_max[v])
                .abs()
                .max((self.kappa_min[v] - other.kappa_min[v]).abs());
            e.kappa = e.kappa.max(dk / scale);
            let (kx, kn) = (self.kappa_max[v], self.kappa_min[v]);
            if (kx - kn).abs() > 0.1 * kx.abs().max(kn.abs()) {
                let a = angle(self.dir_kappa_max[v], other.dir_kappa_max[v], true).max(angle(
                    self.dir_kappa_min[v],
                    other.dir_kappa_min[v],
                    true,
                ));
                e.direction_deg = e.direction_deg.max(a);
                e.directions_checked += 1;
            }
        }
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_field_differs_from_itself_by_nothing_and_from_a_turned_copy_by_the_turn() {
        let mesh = crate::generate::torus(1.0, 0.35, 32, 16);
        let (_, _, field) = CurvatureField::for_mesh(&mesh, &crate::CurvatureOptions::default());
        let same = field.difference(&field);
        assert_eq!(
            (
                same.kappa,
                same.normal_deg,
                same.direction_deg,
                same.validity
            ),
            (0.0, 0.0, 0.0, 0)
        );
        assert!(same.directions_checked > 0 && same.scale.0 > 0.0);
        let mut other = field.clone();
        let turn = glam::Quat::from_rotation_z(2f32.to_radians());
        for d in &mut other.dir_kappa_max {
            *d = turn * *d;
        }
        other.kappa_min[3] += 0.01 * same.scale.0;
        other.valid[5] = !other.valid[5];
        let e = field.difference(&other);
        assert!((e.direction_deg - 2.0).abs() < 0.2, "{}", e.direction_deg);
        assert!((e.kappa - 0.01).abs() < 1e-4, "{}", e.kappa);
        assert_eq!(e.validity, 1);
    }
}
