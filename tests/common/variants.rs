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

/// (f) a twist helper inserted halfway down the bone of `joint` (which has one child joint),
/// as skinning rigs have (MakeHuman's `upperleg02`): a joint `<joint>Twist` with three rotation
/// channels in `joint`'s order, turning `twist_deg(frame)` about the bone, and the child's
/// rotation written as `R_twistᵀ · R_child`, so that every joint of `b` moves exactly as it did.
pub fn with_twist_helper(b: &Bvh, joint: &str, twist_deg: impl Fn(usize) -> f64) -> Bvh {
    let p = b.joint_index(joint).expect("the joint");
    let children: Vec<usize> = (0..b.joints.len())
        .filter(|&c| b.joints[c].parent == Some(p))
        .collect();
    assert_eq!(children.len(), 1, "{joint} has one child joint");
    let c = children[0];
    let (_, order_p) = rotation_columns(b, p).expect("three rotation channels");
    let (c_cols, order_c) = rotation_columns(b, c).expect("three rotation channels");
    let bone = b.joints[c].offset;
    let axis = nalgebra::Unit::new_normalize(bone);
    // the joints: the helper right after `joint`, later indices and columns shifted
    let at = p + 1;
    let h_first = b.joints[p].first_channel + b.joints[p].channels.len();
    let mut out = b.clone();
    for j in out.joints.iter_mut() {
        j.parent = j.parent.map(|q| if q >= at { q + 1 } else { q });
        if j.first_channel >= h_first {
            j.first_channel += 3;
        }
    }
    out.joints[c].parent = Some(at);
    out.joints[c].offset = 0.5 * bone;
    let rot = [Channel::Xrotation, Channel::Yrotation, Channel::Zrotation];
    out.joints.insert(
        at,
        articula::io::bvh::BvhJoint {
            name: format!("{joint}Twist"),
            parent: Some(p),
            offset: 0.5 * bone,
            channels: order_p.axes().map(|a| rot[a]).to_vec(),
            first_channel: h_first,
            end_sites: vec![],
            line: 0,
        },
    );
    out.channel_count = b.channel_count + 3;
    out.motion = Vec::with_capacity(b.frames * out.channel_count);
    for k in 0..b.frames {
        let mut row = b.frame(k).to_vec();
        let twist = Rotation3::from_axis_angle(&axis, twist_deg(k).to_radians()).into_inner();
        let r_c = euler_to_matrix(order_c, c_cols.map(|col| row[col].to_radians()));
        let a_c = matrix_to_euler(order_c, &(twist.transpose() * r_c));
        for i in 0..3 {
            row[c_cols[i]] = a_c[i].to_degrees();
        }
        let a_h = matrix_to_euler(order_p, &twist).map(f64::to_degrees);
        out.motion.extend_from_slice(&row[..h_first]);
        out.motion.extend_from_slice(&a_h);
        out.motion.extend_from_slice(&row[h_first..]);
    }
    out
}

/// (g) the leaf joint `joint` (no child joints) replaced by an End Site at its offset, its
/// channels gone: a skeleton whose feet end without toe joints, as some optical systems write
/// them.
pub fn without_leaf_joint(b: &Bvh, joint: &str) -> Bvh {
    let j = b.joint_index(joint).expect("the joint");
    assert!(
        b.joints.iter().all(|c| c.parent != Some(j)),
        "{joint} has child joints"
    );
    let (first, count) = (b.joints[j].first_channel, b.joints[j].channels.len());
    let mut out = b.clone();
    let removed = out.joints.remove(j);
    let parent = removed.parent.expect("not the root");
    out.joints[parent].end_sites.push(removed.offset);
    for c in out.joints.iter_mut() {
        if c.first_channel > first {
            c.first_channel -= count;
        }
        if let Some(p) = c.parent.as_mut()
            && *p > j
        {
            *p -= 1;
        }
    }
    out.channel_count = b.channel_count - count;
    out.motion = (0..b.frames)
        .flat_map(|k| {
            let row = b.frame(k);
            row[..first]
                .iter()
                .chain(&row[first + count..])
                .copied()
                .collect::<Vec<_>>()
        })
        .collect();
    out
}

/// (f) the whole take turned by `deg` about the vertical axis `up` (0 x, 1 y, 2 z: a change of
/// heading, about the vertical line through the file's origin, the floor unchanged) and the
/// root's rotation channels written in `order`: root rotations `H R`, positions `H p`. With
/// the vertical axis in the middle of `order` and a heading near 90°, the root's Euler triple
/// sits near gimbal lock (the Xia takes' Hips).
pub fn turned_heading(b: &Bvh, up: usize, deg: f64, order: EulerOrder) -> Bvh {
    let j = b.joints.iter().position(|j| j.parent.is_none()).unwrap();
    let (cols, old) = rotation_columns(b, j).expect("a root with three rotations");
    let h = articula::rotation::axis_rotation(up, deg.to_radians());
    let mut out = b.clone();
    let joint = &mut out.joints[j];
    let slots: Vec<usize> = (0..joint.channels.len())
        .filter(|&i| joint.channels[i].is_rotation())
        .collect();
    let rot = [Channel::Xrotation, Channel::Yrotation, Channel::Zrotation];
    for (slot, axis) in slots.iter().zip(order.axes()) {
        joint.channels[*slot] = rot[axis];
    }
    let first = joint.first_channel;
    let position: Vec<(usize, usize)> = (joint.channels.iter().enumerate())
        .filter_map(|(i, c)| match c {
            Channel::Xposition => Some((first + i, 0)),
            Channel::Yposition => Some((first + i, 1)),
            Channel::Zposition => Some((first + i, 2)),
            _ => None,
        })
        .collect();
    for k in 0..b.frames {
        let row = b.frame(k);
        let r = euler_to_matrix(old, cols.map(|c| row[c].to_radians()));
        let a = matrix_to_euler(order, &(h * r));
        let base = k * b.channel_count;
        for i in 0..3 {
            out.motion[base + cols[i]] = a[i].to_degrees();
        }
        let mut p = Vector3::zeros();
        for &(c, axis) in &position {
            p[axis] = row[c];
        }
        let turned = h * p;
        for &(c, axis) in &position {
            out.motion[base + c] = turned[axis];
        }
    }
    out
}
