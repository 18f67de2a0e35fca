//! 6×6 spatial inertias (composite and articulated) as plain matrices, angular first, and the
//! two operations CRBA and ABA need on them: apply to a motion, and move to the parent frame.
//! A rigid-body [`SpatialInertia`](crate::spatial::SpatialInertia) becomes one with
//! `to_matrix()`; an articulated inertia is a general symmetric positive semi-definite matrix.

use crate::spatial::{AxisRotation, FastTransform, ForceVec, MotionVec, SpatialTransform, skew};
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

/// [`to_parent`] for a transform in fast form: a coordinate-axis rotation turns each 3×3 block
/// with 24 multiplications instead of 54, and a zero translation (the zero-length fictitious
/// links of a BVH euler model) skips the shift.
#[inline]
pub fn to_parent_fast(x: &FastTransform, i: &Matrix6<f64>) -> Matrix6<f64> {
    let (trans, rot) = match x {
        FastTransform::Axis { trans, rot } => (trans, rot),
        FastTransform::General(x) => return to_parent(x, i),
    };
    let a1 = sandwich(rot, &i.fixed_view::<3, 3>(0, 0).into_owned());
    let b1 = sandwich(rot, &i.fixed_view::<3, 3>(0, 3).into_owned());
    let c1 = sandwich(rot, &i.fixed_view::<3, 3>(3, 3).into_owned());
    let (a2, b2) = if *trans == nalgebra::Vector3::zeros() {
        (a1, b1)
    } else {
        let p = skew(trans);
        let pc = p * c1;
        let bp = b1 * p;
        (a1 - bp - bp.transpose() - pc * p, b1 + pc)
    };
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&a2);
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&b2);
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&b2.transpose());
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&c1);
    out
}

/// `R M Rᵀ` for a coordinate-axis rotation `R`: rotate the columns (`R M`), then the rows
/// (`(R M) Rᵀ`, whose rows are `R` times the rows of `R M`).
#[inline]
fn sandwich(r: &AxisRotation, m: &Matrix3<f64>) -> Matrix3<f64> {
    let rm = Matrix3::from_columns(&[
        r.rotate(&m.column(0).into_owned()),
        r.rotate(&m.column(1).into_owned()),
        r.rotate(&m.column(2).into_owned()),
    ]);
    Matrix3::from_rows(&[
        r.rotate(&rm.row(0).transpose()).transpose(),
        r.rotate(&rm.row(1).transpose()).transpose(),
        r.rotate(&rm.row(2).transpose()).transpose(),
    ])
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
            // the fast form, with and without translation, about each coordinate axis
            for axis in 0..3 {
                for trans in [x.trans, Vector3::zeros()] {
                    let rot = AxisRotation::new(axis, 0.9);
                    let fast = FastTransform::Axis { trans, rot };
                    let a = to_parent_fast(&fast, &m);
                    let b = to_parent(&fast.to_transform(), &m);
                    assert!((a - b).norm() < 1e-12, "axis {axis}: {}", (a - b).norm());
                }
            }
        }
    }
}
