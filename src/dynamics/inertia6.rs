//! Symmetric 6×6 spatial inertias (articulated ones, for ABA) in the 21 numbers that define
//! them: `I = [A B; Bᵀ C]`, angular first, `A` and `C` symmetric (Featherstone 2008 §7.1: an
//! articulated-body inertia is symmetric positive semi-definite but not a rigid body's). ABA
//! keeps them in world axes (as Pinocchio's `oYaba`) about each body's origin, so an
//! articulated inertia is handed to the parent by a shift of reference point (no rotation) and
//! 21 additions, and the 1-DoF reduction `I − U Uᵀ / D` is a rank-1 update of the 21 numbers.

use super::crba::WorldInertia;
use crate::spatial::{ForceVec, MotionVec};
use nalgebra::{Matrix3, Matrix6, Vector3};

/// `[A B; Bᵀ C]` with `A`, `C` symmetric as `[xx, yy, zz, xy, xz, yz]` and `B` full (row-major
/// `b[r][c]`). Units: `A` kg·m², `B` kg·m, `C` kg (about the frame's origin).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SymInertia6 {
    pub a: [f64; 6],
    pub b: [[f64; 3]; 3],
    pub c: [f64; 6],
}

/// `S v` for a symmetric 3×3 `S` stored as `[xx, yy, zz, xy, xz, yz]`.
#[inline]
fn sym_mul(s: &[f64; 6], v: &Vector3<f64>) -> Vector3<f64> {
    let [xx, yy, zz, xy, xz, yz] = *s;
    Vector3::new(
        xx * v.x + xy * v.y + xz * v.z,
        xy * v.x + yy * v.y + yz * v.z,
        xz * v.x + yz * v.y + zz * v.z,
    )
}

/// `s −= k u uᵀ` on the 6 stored numbers of a symmetric 3×3.
#[inline]
fn sym_sub_outer(s: &mut [f64; 6], u: &Vector3<f64>, k: f64) {
    let ku = u * k;
    s[0] -= ku.x * u.x;
    s[1] -= ku.y * u.y;
    s[2] -= ku.z * u.z;
    s[3] -= ku.x * u.y;
    s[4] -= ku.x * u.z;
    s[5] -= ku.y * u.z;
}

impl SymInertia6 {
    /// A rigid body's (or composite's) inertia from its ten numbers: `A = I_O`, `B = [h]×`,
    /// `C = m 1` (`n = I_O ω + h × v`, `f = m v − h × ω`).
    #[inline]
    pub fn from_world(y: &WorldInertia) -> Self {
        let h = &y.h;
        SymInertia6 {
            a: y.i,
            b: [[0.0, -h.z, h.y], [h.z, 0.0, -h.x], [-h.y, h.x, 0.0]],
            c: [y.m, y.m, y.m, 0.0, 0.0, 0.0],
        }
    }

    /// `I · m`: `n = A ω + B v`, `f = Bᵀ ω + C v`.
    #[inline]
    pub fn mul_motion(&self, m: &MotionVec) -> ForceVec {
        let (w, v, b) = (&m.ang, &m.lin, &self.b);
        let bv = Vector3::new(
            b[0][0] * v.x + b[0][1] * v.y + b[0][2] * v.z,
            b[1][0] * v.x + b[1][1] * v.y + b[1][2] * v.z,
            b[2][0] * v.x + b[2][1] * v.y + b[2][2] * v.z,
        );
        let btw = Vector3::new(
            b[0][0] * w.x + b[1][0] * w.y + b[2][0] * w.z,
            b[0][1] * w.x + b[1][1] * w.y + b[2][1] * w.z,
            b[0][2] * w.x + b[1][2] * w.y + b[2][2] * w.z,
        );
        ForceVec {
            ang: sym_mul(&self.a, w) + bv,
            lin: btw + sym_mul(&self.c, v),
        }
    }

    /// `I · [ω; 0]` (a pure rotation, a revolute joint's axis about its own point):
    /// `n = A ω`, `f = Bᵀ ω`.
    #[inline]
    pub fn mul_ang(&self, w: &Vector3<f64>) -> ForceVec {
        let b = &self.b;
        ForceVec {
            ang: sym_mul(&self.a, w),
            lin: Vector3::new(
                b[0][0] * w.x + b[1][0] * w.y + b[2][0] * w.z,
                b[0][1] * w.x + b[1][1] * w.y + b[2][1] * w.z,
                b[0][2] * w.x + b[1][2] * w.y + b[2][2] * w.z,
            ),
        }
    }

    /// `I += o`, number by number.
    #[inline]
    pub fn add(&mut self, o: &SymInertia6) {
        for (x, y) in self.a.iter_mut().zip(&o.a) {
            *x += y;
        }
        for (x, y) in self.c.iter_mut().zip(&o.c) {
            *x += y;
        }
        for (r, s) in self.b.iter_mut().zip(&o.b) {
            for (x, y) in r.iter_mut().zip(s) {
                *x += y;
            }
        }
    }

    /// The rank-1 reduction `I −= k u uᵀ` for a force-like `u = [u_n; u_f]` (ABA's
    /// `I^A − U D⁻¹ Uᵀ` for a 1-DoF joint, `k = 1/D`).
    #[inline]
    pub fn sub_outer(&mut self, u: &ForceVec, k: f64) {
        sym_sub_outer(&mut self.a, &u.ang, k);
        sym_sub_outer(&mut self.c, &u.lin, k);
        let kn = u.ang * k;
        for (r, kr) in self.b.iter_mut().zip(kn.iter()) {
            r[0] -= kr * u.lin.x;
            r[1] -= kr * u.lin.y;
            r[2] -= kr * u.lin.z;
        }
    }

    /// The same inertia about the point `p` (relative to the current reference point, same
    /// axes): `A' = A + B P + (B P)ᵀ − P C P`, `B' = B − P C`, `C' = C` with `P = [p]×` (from
    /// `n_p = n − p × f` and `v = v_p + p × ω`).
    #[inline]
    pub fn move_by(&mut self, p: &Vector3<f64>) {
        // with P = [p]×, every product with P is a cross product: (P X)_col = p × X_col and
        // (X P)_row = X_row × p (6 multiplications each, not a 3×3 product's 27)
        let c = &self.c;
        let cols = [
            Vector3::new(c[0], c[3], c[4]),
            Vector3::new(c[3], c[1], c[5]),
            Vector3::new(c[4], c[5], c[2]),
        ];
        let pc = cols.map(|col| p.cross(&col)); // columns of P C
        let pc_row = |r: usize| Vector3::new(pc[0][r], pc[1][r], pc[2][r]);
        let (pcp0, pcp1, pcp2) = (pc_row(0).cross(p), pc_row(1).cross(p), pc_row(2).cross(p)); // rows of P C P
        let bp = self.b.map(|r| Vector3::new(r[0], r[1], r[2]).cross(p)); // rows of B P
        let a = &mut self.a;
        a[0] += 2.0 * bp[0][0] - pcp0[0];
        a[1] += 2.0 * bp[1][1] - pcp1[1];
        a[2] += 2.0 * bp[2][2] - pcp2[2];
        a[3] += bp[0][1] + bp[1][0] - pcp0[1];
        a[4] += bp[0][2] + bp[2][0] - pcp0[2];
        a[5] += bp[1][2] + bp[2][1] - pcp1[2];
        for (r, br) in self.b.iter_mut().enumerate() {
            for (k, x) in br.iter_mut().enumerate() {
                *x -= pc[k][r];
            }
        }
    }

    /// `tr(A)`.
    #[inline]
    pub fn trace_a(&self) -> f64 {
        self.a[0] + self.a[1] + self.a[2]
    }

    /// `tr(C)`: three times the mass the inertia resists translation with.
    #[inline]
    pub fn trace_c(&self) -> f64 {
        self.c[0] + self.c[1] + self.c[2]
    }

    /// The full 6×6 matrix.
    pub fn to_matrix(&self) -> Matrix6<f64> {
        let s = |x: &[f64; 6]| Matrix3::new(x[0], x[3], x[4], x[3], x[1], x[5], x[4], x[5], x[2]);
        let b = Matrix3::from_fn(|r, c| self.b[r][c]);
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&s(&self.a));
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&b);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&b.transpose());
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&s(&self.c));
        m
    }

    /// The 21 numbers of a symmetric 6×6 matrix (its upper triangle).
    pub fn from_matrix(m: &Matrix6<f64>) -> Self {
        let s = |o: usize| {
            [
                m[(o, o)],
                m[(o + 1, o + 1)],
                m[(o + 2, o + 2)],
                m[(o, o + 1)],
                m[(o, o + 2)],
                m[(o + 1, o + 2)],
            ]
        };
        SymInertia6 {
            a: s(0),
            b: std::array::from_fn(|r| std::array::from_fn(|c| m[(r, c + 3)])),
            c: s(3),
        }
    }
}

#[cfg(test)]
mod tests {
    //! The 21-number operations are the 6×6 matrix operations they replace.
    use super::*;
    use crate::dynamics::samples::{SplitMix64, random_inertia};
    use crate::spatial::SpatialTransform;
    use nalgebra::Vector6;

    fn random_sym(rng: &mut SplitMix64) -> SymInertia6 {
        // a rigid body's, then a general symmetric perturbation (articulated inertias are not
        // rigid-body ones)
        let y = WorldInertia::of_body(
            &random_inertia(rng, 0.1, 20.0),
            &SpatialTransform::new(*rng.rotation().to_rotation_matrix().matrix(), rng.vec3(2.0)),
        );
        let mut m = SymInertia6::from_world(&y).to_matrix();
        let (u, w) = (rng.vec3(1.0), rng.vec3(1.0));
        let g = Vector6::new(u.x, u.y, u.z, w.x, w.y, w.z);
        m += g * g.transpose();
        SymInertia6::from_matrix(&m)
    }

    #[test]
    fn the_21_numbers_act_as_the_6x6_matrix() {
        let mut rng = SplitMix64(5);
        for _ in 0..20 {
            let (i, j) = (random_sym(&mut rng), random_sym(&mut rng));
            let (mi, mj) = (i.to_matrix(), j.to_matrix());
            assert_eq!(SymInertia6::from_matrix(&mi), i);
            let s = MotionVec::new(rng.vec3(1.0), rng.vec3(1.0));
            let f = i.mul_motion(&s).to_vector6();
            assert!((f - mi * s.to_vector6()).norm() < 1e-12 * mi.norm());
            let w = MotionVec::new(s.ang, Vector3::zeros());
            let f = i.mul_ang(&w.ang).to_vector6();
            assert!((f - mi * w.to_vector6()).norm() < 1e-12 * mi.norm());
            let mut sum = i;
            sum.add(&j);
            assert!((sum.to_matrix() - (mi + mj)).norm() < 1e-12 * mi.norm());
            let u = ForceVec::new(rng.vec3(1.0), rng.vec3(1.0));
            let mut red = i;
            red.sub_outer(&u, 0.7);
            let uv = u.to_vector6();
            let want = mi - uv * uv.transpose() * 0.7;
            assert!((red.to_matrix() - want).norm() < 1e-12 * mi.norm());
        }
    }

    #[test]
    fn moving_the_reference_point_is_the_6x6_congruence() {
        let mut rng = SplitMix64(9);
        for _ in 0..20 {
            let mut i = random_sym(&mut rng);
            let m = i.to_matrix();
            let p = rng.vec3(3.0);
            // about p: X* I X⁻¹ with X the pure translation to p (Featherstone's eq. 2.66)
            let want = SpatialTransform::from_translation(-p).act_inertia_matrix(&m);
            i.move_by(&p);
            let tol = 1e-12 * m.norm() * (1.0 + p.norm_squared());
            assert!((i.to_matrix() - want).norm() < tol);
        }
        // a rigid body's inertia moved to its centre of mass has h = 0 and A = I_c
        let body = random_inertia(&mut rng, 0.1, 20.0);
        let y = WorldInertia::of_body(&body, &SpatialTransform::IDENTITY);
        let mut rigid = SymInertia6::from_world(&y);
        rigid.move_by(&body.com);
        let a = rigid.to_matrix().fixed_view::<3, 3>(0, 0).into_owned();
        assert!((a - body.inertia_com).norm() < 1e-12 * (1.0 + body.inertia_com.norm()));
        assert!(
            rigid
                .b
                .iter()
                .flatten()
                .all(|x| x.abs() < 1e-12 * (1.0 + body.mass))
        );
    }
}
