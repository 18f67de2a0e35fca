//! 6×6 spatial inertias (composite and articulated) as plain matrices, angular first, and the
//! two operations CRBA and ABA need on them: apply to a motion, and move to the parent frame.
//! A rigid-body [`SpatialInertia`](crate::spatial::SpatialInertia) becomes one with
//! `to_matrix()`; an articulated inertia is a general symmetric positive semi-definite matrix.

use crate::spatial::{ForceVec, MotionVec, SpatialTransform, skew};
use nalgebra::{Matrix3, Matrix6, Vector6};

/// `I · m` for a 6×6 inertia (angular first).
#[inline]
pub fn mul_motion(i: &Matrix6<f64>, m: &MotionVec) -> ForceVec {
    let x = i * Vector6::new(m.ang.x, m.ang.y, m.ang.z, m.lin.x, m.lin.y, m.lin.z);
    ForceVec::from_vector6(&x)
}

/// An inertia given in frame i (about i's origin) expressed in frame λ, where `x = λX_i` is the
/// pose of i in λ: `X* I X⁻¹` (Featherstone 2008, eq. 2.66), done block by block.
///
/// With `I = [A B; Bᵀ C]`, `R` and `P = [p]×` the rotation and translation of `x`: first rotate
/// (`A₁ = R A Rᵀ`, …), then move the reference point from i's origin to λ's:
/// `A₂ = A₁ − B₁P + PB₁ᵀ − PC₁P = A₁ − B₁P − (B₁P)ᵀ − PC₁P`, `B₂ = B₁ + PC₁`, `C₂ = C₁`.
#[inline]
pub fn to_parent(x: &SpatialTransform, i: &Matrix6<f64>) -> Matrix6<f64> {
    let r = &x.rot;
    let a: Matrix3<f64> = i.fixed_view::<3, 3>(0, 0).into_owned();
    let b: Matrix3<f64> = i.fixed_view::<3, 3>(0, 3).into_owned();
    let c: Matrix3<f64> = i.fixed_view::<3, 3>(3, 3).into_owned();
    // rotate into λ's axes
    let a1 = r * a * r.transpose();
    let b1 = r * b * r.transpose();
    let c1 = r * c * r.transpose();
    // shift the reference point by p
    let p = skew(&x.trans);
    let pc = p * c1;
    let bp = b1 * p;
    let a2 = a1 - bp - bp.transpose() - pc * p;
    let b2 = b1 + pc;
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&a2);
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&b2);
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&b2.transpose());
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&c1);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::SpatialInertia;
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn to_parent_matches_the_congruence_transform() {
        let x = SpatialTransform::new(
            *UnitQuaternion::from_euler_angles(0.3, -0.7, 1.1)
                .to_rotation_matrix()
                .matrix(),
            Vector3::new(0.2, -0.5, 0.9),
        );
        let i = SpatialInertia::new(
            2.5,
            Vector3::new(0.1, -0.2, 0.3),
            nalgebra::Matrix3::new(0.3, 0.01, 0.0, 0.01, 0.2, 0.02, 0.0, 0.02, 0.1),
        )
        .to_matrix();
        // a general symmetric matrix too (articulated inertias are not rigid-body ones)
        let mut g = i;
        g[(0, 4)] += 0.3;
        g[(4, 0)] += 0.3;
        g[(3, 5)] -= 0.2;
        g[(5, 3)] -= 0.2;
        for m in [i, g] {
            let a = to_parent(&x, &m);
            let b = x.act_inertia_matrix(&m);
            assert!((a - b).norm() < 1e-12, "{}", (a - b).norm());
        }
    }
}
