//! Synthetic models and random states for tests, benchmarks and `articula bench`: random trees,
//! a 7-DoF arm, a 29-DoF humanoid-like tree and a ~100-DoF avatar in the euler joint model
//! (BVH-style: one revolute joint per rotation channel, massless links in between). Every
//! random number comes from [`SplitMix64`] with a fixed seed, so runs are reproducible.

use crate::model::{JointKind, Model, ModelBuilder};
use crate::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny, fast, deterministic 64-bit generator.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
    /// Uniform integer in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.uniform() * n as f64) as usize % n
    }
    /// A vector with entries uniform in `[-r, r)`.
    pub fn vec3(&mut self, r: f64) -> Vector3<f64> {
        Vector3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
    /// A uniformly distributed unit vector.
    pub fn unit3(&mut self) -> Vector3<f64> {
        loop {
            let v = self.vec3(1.0);
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
    /// A uniformly distributed rotation (Shoemake 1992).
    pub fn rotation(&mut self) -> UnitQuaternion<f64> {
        let (u1, u2, u3) = (self.uniform(), self.uniform(), self.uniform());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        UnitQuaternion::new_normalize(Quaternion::new(
            b * (tau * u3).cos(),
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
        ))
    }
}

/// A random physically valid rigid-body inertia: mass in `[m_lo, m_hi)` kg, centre of mass
/// within 0.2 m of the origin, principal moments `(y+z, x+z, x+y)·m` (so the triangle
/// inequality holds) on random axes.
pub fn random_inertia(rng: &mut SplitMix64, m_lo: f64, m_hi: f64) -> SpatialInertia {
    let m = rng.range(m_lo, m_hi);
    let (x, y, z) = (
        rng.range(0.002, 0.03),
        rng.range(0.002, 0.03),
        rng.range(0.002, 0.03),
    );
    let r = rng.rotation().to_rotation_matrix().into_inner();
    let d = Matrix3::from_diagonal(&Vector3::new(y + z, x + z, x + y)) * m;
    SpatialInertia::new(m, rng.vec3(0.2), r * d * r.transpose())
}

/// A random tree of `n` moving bodies: parents chosen among the previous few bodies, joints a
/// mix of revolute (random axis), prismatic, spherical, and a free root when `floating`;
/// random placements and inertias (0.5–5 kg). Gravity `-9.81 z`.
pub fn random_tree(n: usize, seed: u64, floating: bool) -> Model {
    let mut rng = SplitMix64(seed);
    let mut mb = ModelBuilder::new(format!("random{n}"), Vector3::new(0.0, 0.0, -9.81));
    for i in 1..=n {
        let parent = if i == 1 {
            0
        } else {
            i - 1 - rng.below((i - 1).min(3))
        };
        let joint = if i == 1 && floating {
            JointKind::Free
        } else {
            match rng.below(6) {
                0 => JointKind::Prismatic { axis: rng.unit3() },
                1 => JointKind::Spherical,
                _ => JointKind::Revolute { axis: rng.unit3() },
            }
        };
        let placement = SpatialTransform::new(
            rng.rotation().to_rotation_matrix().into_inner(),
            rng.vec3(0.5),
        );
        let inertia = random_inertia(&mut rng, 0.5, 5.0);
        mb.add_body(
            parent,
            format!("b{i}"),
            format!("j{i}"),
            joint,
            placement,
            inertia,
        );
    }
    mb.build()
}

/// A random configuration (revolute in ±π, prismatic in ±0.5 m, uniformly random rotations,
/// free-joint positions in a 1 m box) written to `q` (`nq`).
pub fn random_configuration(model: &Model, rng: &mut SplitMix64, q: &mut [f64]) {
    for i in 1..model.nbodies() {
        let iq = model.idx_q[i];
        match model.joints[i] {
            JointKind::Revolute { .. } => {
                q[iq] = rng.range(-std::f64::consts::PI, std::f64::consts::PI)
            }
            JointKind::Prismatic { .. } => q[iq] = rng.range(-0.5, 0.5),
            JointKind::Spherical => {
                crate::spatial::quat_to_xyzw(&rng.rotation(), &mut q[iq..iq + 4])
            }
            JointKind::Free => {
                let p = rng.vec3(0.5);
                q[iq..iq + 3].copy_from_slice(p.as_slice());
                crate::spatial::quat_to_xyzw(&rng.rotation(), &mut q[iq + 3..iq + 7]);
            }
            JointKind::Fixed => {}
        }
    }
}

/// Fills `x` with entries uniform in `[-r, r)`.
pub fn random_vector(rng: &mut SplitMix64, r: f64, x: &mut [f64]) {
    x.iter_mut().for_each(|e| *e = rng.range(-r, r));
}

/// A solid cylinder-like segment of mass `m` and length `len` along `axis` (unit), centre of
/// mass at mid-length, radius of gyration 0.3 `len` about the transverse axes and 0.1 `len`
/// about its own.
fn segment(m: f64, len: f64, axis: Vector3<f64>) -> SpatialInertia {
    let (kt, ka) = (0.3 * len, 0.1 * len);
    let axial = axis * axis.transpose();
    let inertia = (Matrix3::identity() - axial) * (m * kt * kt) + axial * (m * ka * ka);
    SpatialInertia::new(m, axis * (0.5 * len), inertia)
}

/// A 7-DoF serial arm like `data/arm7.urdf`: axes z, y, z, y, z, y, z (joints 5–7 slightly
/// oblique), ~1.1 m reach, link masses 4.5 down to 1 kg, gravity `-9.81 z`.
pub fn arm7() -> Model {
    let mut mb = ModelBuilder::new("arm7", Vector3::new(0.0, 0.0, -9.81));
    let axes = [
        Vector3::z(),
        Vector3::y(),
        Vector3::z(),
        Vector3::y(),
        Vector3::new(0.0, 0.6, 0.8),
        Vector3::new(0.0, 0.8, -0.6),
        Vector3::new(0.6, 0.0, 0.8),
    ];
    let lengths = [0.2, 0.3, 0.25, 0.2, 0.1, 0.08, 0.05];
    let masses = [4.5, 3.5, 3.0, 2.5, 1.8, 1.2, 1.0];
    let mut offset = 0.1;
    for k in 0..7 {
        let placement = SpatialTransform::new(
            *UnitQuaternion::from_euler_angles(0.1 * k as f64, 0.0, 0.05)
                .to_rotation_matrix()
                .matrix(),
            Vector3::new(0.0, 0.0, offset),
        );
        mb.add_body(
            k,
            format!("link{}", k + 1),
            format!("joint{}", k + 1),
            JointKind::Revolute { axis: axes[k] },
            placement,
            segment(masses[k], lengths[k], Vector3::z()),
        );
        offset = lengths[k];
    }
    mb.build()
}

/// One skeleton segment for the humanoid and avatar generators: its name, parent segment, the
/// offset of its joint from the parent's (m, z up, x forward, y left), and its mass fraction.
struct Seg {
    name: &'static str,
    parent: usize,
    offset: [f64; 3],
    mass: f64,
}

/// A 31-segment skeleton (z up, x forward): pelvis, spine, neck, head, arms with four fingers,
/// legs with toes. Mass fractions roughly de Leva (1996), summing to 1.
const SKELETON: [Seg; 31] = {
    const fn s(name: &'static str, parent: usize, offset: [f64; 3], mass: f64) -> Seg {
        Seg {
            name,
            parent,
            offset,
            mass,
        }
    }
    [
        s("Hips", 0, [0.0, 0.0, 1.0], 0.11),
        s("Spine", 0, [0.0, 0.0, 0.1], 0.08),
        s("Spine1", 1, [0.0, 0.0, 0.15], 0.08),
        s("Spine2", 2, [0.0, 0.0, 0.15], 0.10),
        s("Neck", 3, [0.0, 0.0, 0.15], 0.02),
        s("Neck1", 4, [0.0, 0.0, 0.05], 0.01),
        s("Head", 5, [0.0, 0.0, 0.05], 0.06),
        s("LeftShoulder", 3, [0.0, 0.05, 0.12], 0.01),
        s("LeftArm", 7, [0.0, 0.15, 0.0], 0.027),
        s("LeftForeArm", 8, [0.0, 0.28, 0.0], 0.016),
        s("LeftHand", 9, [0.0, 0.26, 0.0], 0.004),
        s("LeftHandThumb1", 10, [0.03, 0.03, 0.0], 0.0005),
        s("LeftHandIndex1", 10, [0.01, 0.08, 0.0], 0.0005),
        s("LeftHandMiddle1", 10, [0.0, 0.08, 0.0], 0.0005),
        s("LeftHandRing1", 10, [-0.01, 0.08, 0.0], 0.0005),
        s("RightShoulder", 3, [0.0, -0.05, 0.12], 0.01),
        s("RightArm", 15, [0.0, -0.15, 0.0], 0.027),
        s("RightForeArm", 16, [0.0, -0.28, 0.0], 0.016),
        s("RightHand", 17, [0.0, -0.26, 0.0], 0.004),
        s("RightHandThumb1", 18, [0.03, -0.03, 0.0], 0.0005),
        s("RightHandIndex1", 18, [0.01, -0.08, 0.0], 0.0005),
        s("RightHandMiddle1", 18, [0.0, -0.08, 0.0], 0.0005),
        s("RightHandRing1", 18, [-0.01, -0.08, 0.0], 0.0005),
        s("LeftUpLeg", 0, [0.0, 0.09, -0.05], 0.10),
        s("LeftLeg", 23, [0.0, 0.0, -0.43], 0.045),
        s("LeftFoot", 24, [0.0, 0.0, -0.42], 0.012),
        s("LeftToeBase", 25, [0.14, 0.0, -0.06], 0.002),
        s("RightUpLeg", 0, [0.0, -0.09, -0.05], 0.10),
        s("RightLeg", 27, [0.0, 0.0, -0.43], 0.045),
        s("RightFoot", 28, [0.0, 0.0, -0.42], 0.012),
        s("RightToeBase", 29, [0.14, 0.0, -0.06], 0.002),
    ]
};

/// The segment's length direction and length: towards its first child, or 0.1 m on along its
/// own offset for an end segment.
fn segment_extent(k: usize) -> (Vector3<f64>, f64) {
    let child = SKELETON.iter().skip(k + 1).find(|s| s.parent == k);
    let d = match child {
        Some(c) => Vector3::from(c.offset),
        None => Vector3::from(SKELETON[k].offset).normalize() * 0.1,
    };
    let len = d.norm().max(0.02);
    (d / len, len)
}

/// Adds one segment as a chain of revolute joints (one per axis, in order), the segment's
/// inertia on the last body and massless bodies in between (the euler joint model). Returns the
/// last body.
fn add_euler_segment(
    mb: &mut ModelBuilder,
    parent: usize,
    name: &str,
    placement: SpatialTransform,
    axes: &[(char, Vector3<f64>)],
    inertia: SpatialInertia,
) -> usize {
    let mut body = parent;
    let mut x = placement;
    for (k, (c, axis)) in axes.iter().enumerate() {
        let last = k + 1 == axes.len();
        body = mb.add_body(
            body,
            format!("{name}.{c}rotation"),
            format!("{name}.{c}rotation"),
            JointKind::Revolute { axis: *axis },
            x,
            if last { inertia } else { SpatialInertia::ZERO },
        );
        x = SpatialTransform::IDENTITY;
    }
    body
}

/// The avatar in the euler joint model: 31 segments of 75 kg total, the root `Hips` with three
/// prismatic then three revolute joints (`Hips.Xposition`, …, Z, X, Y rotations), every other
/// segment three revolute joints Z, X, Y with massless links in between: 96 DoF. Gravity
/// `-9.81 z`.
pub fn euler_avatar() -> Model {
    let mut mb = ModelBuilder::new("euler_avatar", Vector3::new(0.0, 0.0, -9.81));
    let zxy = [
        ('Z', Vector3::z()),
        ('X', Vector3::x()),
        ('Y', Vector3::y()),
    ];
    let mut last = vec![0; SKELETON.len()];
    for (k, seg) in SKELETON.iter().enumerate() {
        let (dir, len) = segment_extent(k);
        let inertia = segment(75.0 * seg.mass, len, dir);
        let placement = SpatialTransform::from_translation(Vector3::from(seg.offset));
        let parent = if k == 0 {
            // root translation: three prismatic joints from the world
            let mut b = 0;
            for (c, axis) in [
                ('X', Vector3::x()),
                ('Y', Vector3::y()),
                ('Z', Vector3::z()),
            ] {
                b = mb.add_body(
                    b,
                    format!("Hips.{c}position"),
                    format!("Hips.{c}position"),
                    JointKind::Prismatic { axis },
                    if c == 'X' {
                        placement
                    } else {
                        SpatialTransform::IDENTITY
                    },
                    SpatialInertia::ZERO,
                );
            }
            b
        } else {
            last[seg.parent]
        };
        let p = if k == 0 {
            SpatialTransform::IDENTITY
        } else {
            placement
        };
        last[k] = add_euler_segment(&mut mb, parent, seg.name, p, &zxy, inertia);
    }
    mb.build()
}

/// A 29-DoF humanoid-like tree (or 35 with a free root when `floating`), like
/// `data/humanoid.urdf`: legs hip z/x/y, knee y, ankle y/x; lumbar y/x, thorax z; neck y/z;
/// arms shoulder y/x/z, elbow y, wrist y/x; multi-axis joints as revolute chains with 0.05 kg
/// hubs. 75 kg, gravity `-9.81 z`.
pub fn humanoid(floating: bool) -> Model {
    let mut mb = ModelBuilder::new("humanoid", Vector3::new(0.0, 0.0, -9.81));
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    // segment, parent segment, offset, mass (kg), axes
    type Spec = (&'static str, usize, [f64; 3], f64, &'static [(char, u8)]);
    const SPECS: [Spec; 16] = [
        ("pelvis", 0, [0.0, 0.0, 1.0], 11.0, &[]),
        ("lumbar", 0, [0.0, 0.0, 0.1], 12.0, &[('Y', 1), ('X', 0)]),
        ("thorax", 1, [0.0, 0.0, 0.25], 15.0, &[('Z', 2)]),
        ("head", 2, [0.0, 0.0, 0.3], 5.0, &[('Y', 1), ('Z', 2)]),
        (
            "l_upperarm",
            2,
            [0.0, 0.18, 0.22],
            2.0,
            &[('Y', 1), ('X', 0), ('Z', 2)],
        ),
        ("l_forearm", 4, [0.0, 0.0, -0.28], 1.2, &[('Y', 1)]),
        ("l_hand", 5, [0.0, 0.0, -0.26], 0.45, &[('Y', 1), ('X', 0)]),
        (
            "r_upperarm",
            2,
            [0.0, -0.18, 0.22],
            2.0,
            &[('Y', 1), ('X', 0), ('Z', 2)],
        ),
        ("r_forearm", 7, [0.0, 0.0, -0.28], 1.2, &[('Y', 1)]),
        ("r_hand", 8, [0.0, 0.0, -0.26], 0.45, &[('Y', 1), ('X', 0)]),
        (
            "l_thigh",
            0,
            [0.0, 0.09, -0.05],
            7.5,
            &[('Z', 2), ('X', 0), ('Y', 1)],
        ),
        ("l_shank", 10, [0.0, 0.0, -0.43], 3.3, &[('Y', 1)]),
        ("l_foot", 11, [0.0, 0.0, -0.42], 1.05, &[('Y', 1), ('X', 0)]),
        (
            "r_thigh",
            0,
            [0.0, -0.09, -0.05],
            7.5,
            &[('Z', 2), ('X', 0), ('Y', 1)],
        ),
        ("r_shank", 13, [0.0, 0.0, -0.43], 3.3, &[('Y', 1)]),
        ("r_foot", 14, [0.0, 0.0, -0.42], 1.05, &[('Y', 1), ('X', 0)]),
    ];
    let mut last = vec![0; SPECS.len()];
    for (k, &(name, parent, offset, mass, axes)) in SPECS.iter().enumerate() {
        let placement = SpatialTransform::from_translation(Vector3::from(offset));
        let len = if name.contains("foot") { 0.2 } else { 0.3 };
        let dir = if name.contains("foot") { x } else { -z };
        let inertia = segment(mass, len, dir);
        if k == 0 {
            last[0] = if floating {
                mb.add_body(0, name, "root", JointKind::Free, placement, inertia)
            } else {
                // fixed base: the pelvis welded to the world
                0
            };
            continue;
        }
        let mut body = last[parent];
        let mut xp = placement;
        for (a, &(c, ax)) in axes.iter().enumerate() {
            let axis = [x, y, z][ax as usize];
            let last_axis = a + 1 == axes.len();
            let hub = SpatialInertia::new(0.05, Vector3::zeros(), Matrix3::identity() * 1e-5);
            body = mb.add_body(
                body,
                if last_axis {
                    name.to_string()
                } else {
                    format!("{name}_hub{a}")
                },
                format!("{name}_{}", c.to_ascii_lowercase()),
                JointKind::Revolute { axis },
                xp,
                if last_axis { inertia } else { hub },
            );
            xp = SpatialTransform::IDENTITY;
        }
        last[k] = body;
    }
    mb.build()
}
