//! The same motion written another way (issue 13's metamorphic variants), generated from any
//! take: every function returns a take whose joints move exactly as the input's do in the world.

use articula::io::bvh::{Bvh, Channel};
use articula::rotation::{EulerOrder, euler_to_matrix, matrix_to_euler};
use nalgebra::{Matrix3, Rotation3, Vector3};

/// The rotation taking +X to `d` (any, if `d` is zero).
pub fn x_to(d: &Vector3<f64>) -> Matrix3<f64> {
    if d.norm() < 1e-12 {
        return Matrix3::identity();
    }
    Rotation3::rotation_between(&Vector3::x(), d)
        .unwrap_or_else(|| Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI))
        .into_inner()
}

/// The rotation columns of `joint` (file order) and its Euler order, if it has three.
fn rotation_columns(b: &Bvh, j: usize) -> Option<([usize; 3], EulerOrder)> {
    let joint = &b.joints[j];
    let cols: Vec<usize> = (0..joint.channels.len())
        .filter(|&i| joint.channels[i].is_rotation())
        .map(|i| joint.first_channel + i)
        .collect();
    Some(([cols[0], cols[1], cols[2]], joint.euler_order()?)).filter(|_| cols.len() == 3)
}

/// Whether (a) applies: no position channels below the root.
pub fn lying_along_x_applies(b: &Bvh) -> bool {
    b.joints
        .iter()
        .all(|j| j.parent.is_none() || !j.has_position())
        && (0..b.joints.len()).all(|j| rotation_columns(b, j).is_some())
}

/// (a) `b` with every joint frame turned by a constant `C_j` so that the bone to its first
/// child (or End Site) lies along local +X: offsets `C_parentᵀ o`, rotations `C_parentᵀ R C_j`
/// in the joint's own Euler order. Every joint's world position is unchanged; the OFFSET-only
/// pose becomes a chain lying along +X (LaFAN1, Bandai).
pub fn lying_along_x(b: &Bvh) -> Bvh {
    let n = b.joints.len();
    let c: Vec<Matrix3<f64>> = (0..n)
        .map(|j| {
            let child = b
                .joints
                .iter()
                .find(|k| k.parent == Some(j))
                .map(|k| k.offset);
            x_to(
                &child
                    .or(b.joints[j].end_sites.first().copied())
                    .unwrap_or_default(),
            )
        })
        .collect();
    let mut out = b.clone();
    for (j, joint) in out.joints.iter_mut().enumerate() {
        let cp = joint.parent.map_or(Matrix3::identity(), |p| c[p]);
        assert!(joint.parent.is_none() || !joint.has_position());
        joint.offset = cp.transpose() * joint.offset;
        for s in joint.end_sites.iter_mut() {
            *s = c[j].transpose() * *s;
        }
    }
    for k in 0..b.frames {
        let row = b.frame(k).to_vec();
        for (j, joint) in b.joints.iter().enumerate() {
            let (cols, order) = rotation_columns(b, j).expect("three rotation channels");
            let r = euler_to_matrix(order, cols.map(|c| row[c].to_radians()));
            let cp = joint.parent.map_or(Matrix3::identity(), |p| c[p]);
            let a = matrix_to_euler(order, &(cp.transpose() * r * c[j]));
            for i in 0..3 {
                out.motion[k * b.channel_count + cols[i]] = a[i].to_degrees();
            }
        }
    }
    out
}

/// (b) every joint's rotation channels in another order (the next one of
/// [`EulerOrder::ALL`]), the angles rewritten so that each joint's rotation is unchanged.
pub fn another_rotation_order(b: &Bvh) -> Bvh {
    let mut out = b.clone();
    for j in 0..b.joints.len() {
        let Some((cols, order)) = rotation_columns(b, j) else {
            continue;
        };
        let i = EulerOrder::ALL.iter().position(|o| *o == order).unwrap();
        let new = EulerOrder::ALL[(i + 1) % 6];
        let joint = &mut out.joints[j];
        let slots: Vec<usize> = (0..joint.channels.len())
            .filter(|&i| joint.channels[i].is_rotation())
            .collect();
        let rot = [Channel::Xrotation, Channel::Yrotation, Channel::Zrotation];
        for (slot, axis) in slots.iter().zip(new.axes()) {
            joint.channels[*slot] = rot[axis];
        }
        for k in 0..b.frames {
            let row = b.frame(k);
            let r = euler_to_matrix(order, cols.map(|c| row[c].to_radians()));
            let a = matrix_to_euler(new, &r);
            for i in 0..3 {
                out.motion[k * b.channel_count + cols[i]] = a[i].to_degrees();
            }
        }
    }
    out
}

/// (c) every length (offsets, End Sites, position channels) multiplied by `k`: written in
/// another unit.
pub fn in_another_unit(b: &Bvh, k: f64) -> Bvh {
    let mut out = b.clone();
    for joint in &mut out.joints {
        joint.offset *= k;
        for s in &mut joint.end_sites {
            *s *= k;
        }
    }
    for joint in &b.joints {
        for (i, c) in joint.channels.iter().enumerate() {
            if c.is_rotation() {
                continue;
            }
            for f in 0..b.frames {
                out.motion[f * b.channel_count + joint.first_channel + i] *= k;
            }
        }
    }
    out
}

/// (d) every joint's Euler triple on the other Tait–Bryan branch, `(a + 180°, 180° − b,
/// c + 180°)` (the same rotation), for the frames in `frames`.
pub fn other_euler_branch(b: &Bvh, frames: std::ops::Range<usize>) -> Bvh {
    let mut out = b.clone();
    for j in 0..b.joints.len() {
        let Some((cols, order)) = rotation_columns(b, j) else {
            continue;
        };
        for k in frames.clone() {
            let row = b.frame(k);
            let [x, y, z] = cols.map(|c| row[c]);
            let r = euler_to_matrix(order, [x, y, z].map(f64::to_radians));
            let other = [x + 180.0, 180.0 - y, z + 180.0];
            let r2 = euler_to_matrix(order, other.map(f64::to_radians));
            assert!(
                (r - r2).norm() < 1e-9,
                "the other branch is the same rotation"
            );
            for i in 0..3 {
                out.motion[k * b.channel_count + cols[i]] = other[i];
            }
        }
    }
    out
}

/// (e) every joint renamed `J0`, `J1`, … (in file order).
pub fn renamed(b: &Bvh) -> Bvh {
    let mut out = b.clone();
    for (j, joint) in out.joints.iter_mut().enumerate() {
        joint.name = format!("J{j}");
    }
    out
}
