//! A [`Model`] as MuJoCo's MJCF, for simulating and checking articula's avatars in MuJoCo.
//!
//! Layout (MuJoCo XML reference, <https://mujoco.readthedocs.io/en/stable/XMLreference.html>):
//! - one MuJoCo body per *group* of articula bodies: a body joins its parent's group when the
//!   parent is massless, shapeless and has no other child, the body sits at the parent's origin
//!   with the same axes (identity placement) and both joints are revolute or prismatic. That is
//!   the euler model's chain of one BVH joint (its fictitious links): MuJoCo applies a body's
//!   joints one after the other, each about its axis in the frame the previous ones left
//!   (`mj_kinematics`), which is articula's `R = R_c1·R_c2·R_c3`. A group is named as its last
//!   body (the one with the link's mass and shape), its joints as articula's joints;
//! - the root group under the world becomes a `<freejoint/>` when it is articula's floating
//!   root: a free joint (ball model), or three prismatic joints along distinct coordinate axes
//!   then three revolute joints about distinct ones (euler model). MuJoCo's coordinates of it
//!   differ from articula's (qpos: world position, quaternion w first; qvel: linear velocity in
//!   the world, angular in the body; see `tools/check_mujoco.py` for the conversion);
//! - a spherical joint is `type="ball"` (quaternion w first; qvel the angular velocity in the
//!   child frame, as articula's); a free joint below the root (`--joint-translations keep` in
//!   the ball model) is three slides along the parent's axes then a ball, since MuJoCo allows
//!   free joints only on bodies of the world;
//! - `<inertial>` is the group's link: `pos` its centre of mass, `mass`, `fullinertia` about
//!   the centre of mass in body axes. MuJoCo refuses principal moments with `A + B < C`
//!   (Corke's Puma 560 link 3 has them): the file then asks for `balanceinertia` and a comment
//!   names the links MuJoCo changes. `inertiafromgeom="false"`: geometry never adds mass. A
//!   massless moving body (none in a BVH model: fictitious links are merged) gets MuJoCo's
//!   `boundmass`/`boundinertia` floors, 1e-9 kg and 1e-12 kg·m²;
//! - each link's superquadric shape ([`Superquadric`](crate::model::Superquadric), semi-axes
//!   a, b, c) is an ellipsoid of the same semi-axes, centre and axes; links collide with the
//!   floor but not with each other (`contype="2" conaffinity="1"`, the floor the reverse);
//! - a floor plane at the given height, normal along up (−gravity); `<option gravity>` is the
//!   model's gravity, the integrator RK4 (at MuJoCo's 2 ms step a passive ball-model avatar
//!   falls and settles on the floor with it; with Euler its light hands go unstable); lengths
//!   are metres, angles radians. The euler model's hinge chains are singular at gimbal lock, as
//!   articula's D(q) is: a passive ragdoll of it reaches that within a fraction of a second, so
//!   simulate the ball model (`armature` on the joints would regularize it, but changes the
//!   dynamics `mj_inverse` computes);
//! - the first frame of the take as the keyframe `first_frame` (MuJoCo's `qpos0` is the rest
//!   pose at the world's origin, half under the floor);
//! - one `<motor>` per degree of freedom of every joint but the free root (a ball joint has
//!   three, about its x, y and z axes: `gear="g 0 0"` …), named as articula's velocity
//!   coordinate, with the gear given (1 when none is: the control is then the joint torque,
//!   N·m, or force, N) and no control limits; viscous damping `b` is the joint's `damping`.
//!
//! Numbers are printed in their shortest exact form, so MuJoCo reads articula's values.

use crate::error::Error;
use crate::io::xml::{attr, comment, num, nums, vec3};
use crate::model::{JointKind, Model, Superquadric};
use crate::spatial::SpatialTransform;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use std::fmt::Write;

/// What the MJCF adds to the model.
#[derive(Debug, Clone, Default)]
pub struct MjcfOptions {
    /// Height of the floor plane along up (m); `None`: no floor.
    pub floor: Option<f64>,
    /// Gear of the motor of each velocity coordinate (`nv` entries); empty: 1 for every one.
    pub gear: Vec<f64>,
    /// Where the gears come from, for the file's header (e.g. "the workbench's motor drives").
    pub gear_source: Option<String>,
    /// A configuration (articula's `q`, `nq` entries) written as the keyframe `first_frame`
    /// in MuJoCo's coordinates (a viewer's "load key" poses the avatar there; `qpos0` is the
    /// rest pose at the world's origin); `None`: no keyframe.
    pub keyframe: Option<Vec<f64>>,
}

/// How one MuJoCo body moves relative to its parent.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Root {
    /// The group's joints as they are.
    Joints,
    /// A `<freejoint/>` replacing the group's 6 coordinates.
    Free,
}

/// A MuJoCo body: articula bodies `members` (first to last), placed by the first's placement.
#[derive(Debug, Clone)]
struct Group {
    /// The MuJoCo body's name (and its free joint's): see [`name_groups`].
    name: String,
    members: Vec<usize>,
    root: Root,
    children: Vec<usize>,
}

/// The MJCF text of `model` (see the module doc).
///
/// Errors: two bodies with the same name, or a `gear` list or keyframe of the wrong length.
pub fn model_to_mjcf(model: &Model, opts: &MjcfOptions) -> Result<String, Error> {
    check_names(model)?;
    if opts.keyframe.as_ref().is_some_and(|q| q.len() != model.nq) {
        return Err(Error::Invalid(format!(
            "a keyframe of {} coordinates for a model with nq = {}",
            opts.keyframe.as_ref().map_or(0, Vec::len),
            model.nq
        )));
    }
    if !opts.gear.is_empty() && opts.gear.len() != model.nv {
        return Err(Error::Invalid(format!(
            "{} motor gears for {} degrees of freedom",
            opts.gear.len(),
            model.nv
        )));
    }
    let groups = group_bodies(model);
    let up = up_axis(&model.gravity);
    let mut out = String::new();
    let w = &mut out;
    // writing to a String cannot fail
    let _ = writeln!(w, "<?xml version=\"1.0\"?>");
    header(w, model, opts, &groups);
    let _ = writeln!(w, "<mujoco model=\"{}\">", attr(&model.name));
    // MuJoCo refuses principal moments that break A + B >= C (Corke's Puma 560 link 3 does):
    // it balances them, saying so, rather than not loading
    let unbalanced = unbalanced_links(model, &groups);
    if !unbalanced.is_empty() {
        let _ = writeln!(
            w,
            "  <!-- {}: principal moments of inertia break A + B >= C, which MuJoCo refuses; \
             balanceinertia raises the smallest, so these links differ from articula's -->",
            comment(&unbalanced.join(", "))
        );
    }
    let _ = writeln!(
        w,
        "  <compiler angle=\"radian\" inertiafromgeom=\"false\" autolimits=\"true\" \
         boundmass=\"1e-9\" boundinertia=\"1e-12\"{}/>",
        if unbalanced.is_empty() {
            ""
        } else {
            " balanceinertia=\"true\""
        }
    );
    // RK4: a passive ball-model avatar falls and settles at MuJoCo's 2 ms step, where Euler's
    // light hands and feet go unstable; the integrator leaves mj_inverse unchanged
    let _ = writeln!(
        w,
        "  <option gravity=\"{}\" integrator=\"RK4\"/>",
        vec3(&model.gravity)
    );
    let _ = writeln!(w, "  <worldbody>");
    if let Some(h) = opts.floor {
        let _ = writeln!(
            w,
            "    <geom name=\"floor\" type=\"plane\" size=\"0 0 1\" pos=\"{}\"{} \
             contype=\"1\" conaffinity=\"2\" rgba=\"0.8 0.8 0.8 1\"/>",
            vec3(&(up * h)),
            quat_attr(&rotation_z_to(&up))
        );
    }
    for (g, group) in groups.iter().enumerate() {
        if model.parent[group.members[0]] == 0 {
            write_group(w, model, &groups, g, 2);
        }
    }
    let _ = writeln!(w, "  </worldbody>");
    write_root_map(w, model, &groups);
    if let Some(q) = &opts.keyframe {
        let qpos = mujoco_qpos(model, &groups, q);
        let _ = writeln!(w, "  <keyframe>");
        let _ = writeln!(
            w,
            "    <key name=\"first_frame\" qpos=\"{}\"/>",
            nums(&qpos)
        );
        let _ = writeln!(w, "  </keyframe>");
    }
    write_actuators(w, model, opts, &groups);
    let _ = writeln!(w, "</mujoco>");
    Ok(out)
}

/// MuJoCo needs unique body names.
fn check_names(model: &Model) -> Result<(), Error> {
    let mut names = std::collections::HashSet::new();
    for n in &model.body_names {
        if !names.insert(n.as_str()) {
            return Err(Error::Invalid(format!(
                "two bodies are named {n:?}: MuJoCo body names must be unique"
            )));
        }
    }
    Ok(())
}

/// The file's opening comment: what it holds and how its coordinates relate to articula's.
fn header(w: &mut String, model: &Model, opts: &MjcfOptions, groups: &[Group]) {
    let free: Vec<String> = groups
        .iter()
        .filter(|g| g.root == Root::Free)
        .flat_map(|g| g.members.iter())
        .flat_map(|&i| coordinate_names(model, i))
        .collect();
    let gear = match (&opts.gear_source, opts.gear.is_empty()) {
        (Some(s), false) => format!("motor gears from {s}"),
        _ => "motor gear 1 on every DoF (articula has no drive settings here): the control is \
              the joint torque (N m) or force (N)"
            .to_string(),
    };
    let _ = writeln!(
        w,
        "<!-- {} as MJCF, written by articula: {} articula bodies in {} MuJoCo bodies, \
         nv = {}, total mass {} kg.\n     \
         SI units, radians; gravity {} m/s^2; {}.\n     \
         root: {}.\n     \
         massless fictitious links of the euler model are merged: their joints are \
         consecutive joints of one body. -->",
        comment(&model.name),
        model.nbodies() - 1,
        groups.len(),
        model.nv,
        num(model.total_mass()),
        vec3(&model.gravity),
        comment(&gear),
        if free.is_empty() {
            "no free joint".to_string()
        } else {
            comment(&format!(
                "a freejoint in place of articula's coordinates {}",
                free.join(", ")
            ))
        }
    );
}

/// The groups whose link's principal moments of inertia `A ≤ B ≤ C` have `A + B < C`.
fn unbalanced_links(model: &Model, groups: &[Group]) -> Vec<String> {
    groups
        .iter()
        .filter(|g| {
            let last = *g.members.last().unwrap_or(&g.members[0]);
            let i = &model.inertia[last];
            let mut m: Vec<f64> = i
                .inertia_com
                .symmetric_eigenvalues()
                .iter()
                .copied()
                .collect();
            m.sort_by(f64::total_cmp);
            i.mass > 0.0 && m[0] + m[1] < m[2]
        })
        .map(|g| g.name.clone())
        .collect()
}

/// The velocity coordinate names of body `i`'s joint.
fn coordinate_names(model: &Model, i: usize) -> Vec<String> {
    let iv = model.idx_v[i];
    model.v_names[iv..iv + model.joints[i].nv()].to_vec()
}

/// Articula's bodies in MuJoCo bodies (see the module doc), in body order.
fn group_bodies(model: &Model) -> Vec<Group> {
    let n = model.nbodies();
    let mut nchildren = vec![0usize; n];
    for i in 1..n {
        nchildren[model.parent[i]] += 1;
    }
    let one_dof =
        |k: &JointKind| matches!(k, JointKind::Revolute { .. } | JointKind::Prismatic { .. });
    let mut group_of = vec![usize::MAX; n];
    let mut groups: Vec<Group> = Vec::new();
    for i in 1..n {
        let p = model.parent[i];
        let x = &model.placement[i];
        let merge = p != 0
            && nchildren[p] == 1
            && model.inertia[p].is_zero()
            && model.shapes[p].is_none()
            && x.rot == Matrix3::identity()
            && x.trans == Vector3::zeros()
            && one_dof(&model.joints[i])
            && one_dof(&model.joints[p]);
        if merge {
            group_of[i] = group_of[p];
            groups[group_of[i]].members.push(i);
        } else {
            let g = groups.len();
            group_of[i] = g;
            if p != 0 {
                groups[group_of[p]].children.push(g);
            }
            groups.push(Group {
                name: String::new(),
                members: vec![i],
                root: Root::Joints,
                children: Vec::new(),
            });
        }
    }
    for g in &mut groups {
        if model.parent[g.members[0]] == 0 && is_floating_root(model, &g.members) {
            g.root = Root::Free;
        }
    }
    name_groups(model, &mut groups);
    groups
}

/// A group's name: the part its members' body names share before a `.` (`LeftUpLeg` for
/// `LeftUpLeg.Zrotation`, `LeftUpLeg.Xrotation`, …), else its last body's name; the last
/// bodies' names for every group when those would not be unique.
fn name_groups(model: &Model, groups: &mut [Group]) {
    let last = |g: &Group| model.body_names[*g.members.last().unwrap_or(&0)].clone();
    let shared = |g: &Group| {
        let names: Vec<&str> = g
            .members
            .iter()
            .map(|&i| model.body_names[i].as_str())
            .collect();
        let first = names[0];
        let mut n = first.len();
        for other in &names[1..] {
            n = first
                .char_indices()
                .zip(other.chars())
                .find(|((_, a), b)| a != b)
                .map_or(n.min(other.len()), |((k, _), _)| k.min(n));
        }
        match first[..n].rfind('.') {
            Some(k) if names.len() > 1 && k > 0 => first[..k].to_string(),
            _ => last(g),
        }
    };
    let names: Vec<String> = groups.iter().map(shared).collect();
    let unique = names.iter().collect::<std::collections::HashSet<_>>().len() == names.len();
    for (g, n) in groups.iter_mut().zip(names) {
        g.name = if unique { n } else { last(g) };
    }
}

/// A free joint, or 3 prismatic joints along distinct coordinate axes then 3 revolute joints
/// about distinct ones.
fn is_floating_root(model: &Model, members: &[usize]) -> bool {
    if let [i] = members
        && model.joints[*i] == JointKind::Free
    {
        return true;
    }
    if members.len() != 6 {
        return false;
    }
    let axis_of = |i: usize, revolute: bool| match (model.joints[i], revolute) {
        (JointKind::Revolute { axis }, true) | (JointKind::Prismatic { axis }, false) => {
            (0..3).find(|&k| axis == Vector3::ith(k, 1.0))
        }
        _ => None,
    };
    let distinct = |ids: &[usize], revolute: bool| {
        let axes: Option<Vec<usize>> = ids.iter().map(|&i| axis_of(i, revolute)).collect();
        axes.is_some_and(|a| a[0] != a[1] && a[1] != a[2] && a[0] != a[2])
    };
    distinct(&members[..3], false) && distinct(&members[3..], true)
}

/// One MuJoCo body and, nested, its children.
fn write_group(w: &mut String, model: &Model, groups: &[Group], g: usize, depth: usize) {
    let group = &groups[g];
    let pad = "  ".repeat(depth);
    let first = group.members[0];
    let last = *group.members.last().unwrap_or(&first);
    let x = &model.placement[first];
    let _ = writeln!(
        w,
        "{pad}<body name=\"{}\" pos=\"{}\"{}>",
        attr(&group.name),
        vec3(&x.trans),
        quat_attr(&x.rot)
    );
    if group.root == Root::Free {
        let _ = writeln!(w, "{pad}  <freejoint name=\"{}\"/>", attr(&group.name));
    } else {
        for &i in &group.members {
            write_joint(w, model, i, &pad);
        }
    }
    let inertia = &model.inertia[last];
    if inertia.mass > 0.0 {
        let c = &inertia.inertia_com;
        let _ = writeln!(
            w,
            "{pad}  <inertial pos=\"{}\" mass=\"{}\" fullinertia=\"{}\"/>",
            vec3(&inertia.com),
            num(inertia.mass),
            nums(&[
                c[(0, 0)],
                c[(1, 1)],
                c[(2, 2)],
                c[(0, 1)],
                c[(0, 2)],
                c[(1, 2)]
            ])
        );
    }
    if let Some(s) = &model.shapes[last] {
        write_shape(w, &group.name, s, &pad);
    }
    for &c in &group.children {
        write_group(w, model, groups, c, depth + 1);
    }
    let _ = writeln!(w, "{pad}</body>");
}

/// The MuJoCo joint(s) of articula body `i` (a non-root free joint: three slides and a ball).
fn write_joint(w: &mut String, model: &Model, i: usize, pad: &str) {
    let name = attr(&model.joint_names[i]);
    let b = model.damping.get(model.idx_v[i]).copied().unwrap_or(0.0);
    let damping = if b != 0.0 {
        format!(" damping=\"{}\"", num(b))
    } else {
        String::new()
    };
    match model.joints[i] {
        JointKind::Revolute { axis } | JointKind::Prismatic { axis } => {
            let kind = if matches!(model.joints[i], JointKind::Revolute { .. }) {
                "hinge"
            } else {
                "slide"
            };
            let _ = writeln!(
                w,
                "{pad}  <joint name=\"{name}\" type=\"{kind}\" axis=\"{}\"{damping}/>",
                vec3(&axis)
            );
        }
        JointKind::Spherical => {
            let _ = writeln!(w, "{pad}  <joint name=\"{name}\" type=\"ball\"{damping}/>");
        }
        JointKind::Free => {
            for (k, c) in ["x", "y", "z"].iter().enumerate() {
                let _ = writeln!(
                    w,
                    "{pad}  <joint name=\"{name}:{c}\" type=\"slide\" axis=\"{}\"{damping}/>",
                    vec3(&Vector3::ith(k, 1.0))
                );
            }
            let _ = writeln!(w, "{pad}  <joint name=\"{name}\" type=\"ball\"{damping}/>");
        }
        JointKind::Fixed => {}
    }
}

/// A superquadric as the ellipsoid of its semi-axes (skipped if one is not positive).
fn write_shape(w: &mut String, body: &str, s: &Superquadric, pad: &str) {
    if !s.size.iter().all(|&a| a.is_finite() && a > 0.0) {
        return;
    }
    let _ = writeln!(
        w,
        "{pad}  <geom name=\"{}\" type=\"ellipsoid\" size=\"{}\" pos=\"{}\"{} contype=\"2\" \
         conaffinity=\"1\" rgba=\"0.7 0.5 0.3 1\"/>",
        attr(body),
        vec3(&s.size),
        vec3(&s.center),
        quat_attr(&s.rot)
    );
}

/// `<custom><text name="articula:ROOT" data="…">` per free joint: the articula coordinates it
/// stands for, `name kind [x y z]` separated by `;` (kind `slide`/`hinge` with its axis in the
/// body frame, or `free`: articula's own free joint), for tools that convert states and
/// forces (`tools/check_mujoco.py`).
fn write_root_map(w: &mut String, model: &Model, groups: &[Group]) {
    let roots: Vec<&Group> = groups.iter().filter(|g| g.root == Root::Free).collect();
    if roots.is_empty() {
        return;
    }
    let _ = writeln!(w, "  <custom>");
    for g in roots {
        let entries: Vec<String> = g
            .members
            .iter()
            .map(|&i| match model.joints[i] {
                JointKind::Revolute { axis } => {
                    format!("{} hinge {}", model.joint_names[i], vec3(&axis))
                }
                JointKind::Prismatic { axis } => {
                    format!("{} slide {}", model.joint_names[i], vec3(&axis))
                }
                _ => format!("{} free", model.joint_names[i]),
            })
            .collect();
        let _ = writeln!(
            w,
            "    <text name=\"articula:{}\" data=\"{}\"/>",
            attr(&g.name),
            attr(&entries.join("; "))
        );
    }
    let _ = writeln!(w, "  </custom>");
}

/// `<actuator>`: a motor per degree of freedom of every joint but a free root.
fn write_actuators(w: &mut String, model: &Model, opts: &MjcfOptions, groups: &[Group]) {
    let gear = |iv: usize| opts.gear.get(iv).copied().unwrap_or(1.0);
    let mut lines = Vec::new();
    for group in groups.iter().filter(|g| g.root == Root::Joints) {
        for &i in &group.members {
            let (iv, joint) = (model.idx_v[i], attr(&model.joint_names[i]));
            let motor = |name: &str, joint: &str, g: String| {
                format!(
                    "    <motor name=\"{}\" joint=\"{joint}\" gear=\"{g}\"/>",
                    attr(name)
                )
            };
            match model.joints[i] {
                JointKind::Revolute { .. } | JointKind::Prismatic { .. } => {
                    lines.push(motor(&model.v_names[iv], &joint, num(gear(iv))));
                }
                JointKind::Spherical | JointKind::Free => {
                    // a free joint below the root: its three slides, then its ball
                    let slides = model.joints[i].nv() - 3;
                    for (k, c) in ["x", "y", "z"].iter().enumerate().take(slides) {
                        let j = format!("{joint}:{c}");
                        lines.push(motor(&model.v_names[iv + k], &j, num(gear(iv + k))));
                    }
                    for k in 0..3 {
                        let mut axis = [0.0; 3];
                        axis[k] = gear(iv + slides + k);
                        lines.push(motor(&model.v_names[iv + slides + k], &joint, nums(&axis)));
                    }
                }
                JointKind::Fixed => {}
            }
        }
    }
    if lines.is_empty() {
        return;
    }
    let _ = writeln!(w, "  <actuator>");
    for l in lines {
        let _ = writeln!(w, "{l}");
    }
    let _ = writeln!(w, "  </actuator>");
}

/// Articula's configuration `q` as MuJoCo's `qpos`, joint by joint in the file's order (the
/// groups depth first): a free root's world position and quaternion (w first), its members'
/// transforms composed (its parent is the world); hinge and slide angles as they are; a ball's quaternion w first; a free joint
/// below the root its position then its quaternion.
fn mujoco_qpos(model: &Model, groups: &[Group], q: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(model.nq + 1);
    let mut stack: Vec<usize> = (0..groups.len())
        .rev()
        .filter(|&g| model.parent[groups[g].members[0]] == 0)
        .collect();
    while let Some(g) = stack.pop() {
        let group = &groups[g];
        if group.root == Root::Free {
            let x = group
                .members
                .iter()
                .fold(SpatialTransform::IDENTITY, |x, &i| {
                    let (j, iq) = (&model.joints[i], model.idx_q[i]);
                    x.compose(&model.placement[i])
                        .compose(&j.transform(&q[iq..iq + j.nq()]))
                });
            let r = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(x.rot));
            out.extend([x.trans.x, x.trans.y, x.trans.z, r.w, r.i, r.j, r.k]);
        } else {
            for &i in &group.members {
                let iq = model.idx_q[i];
                match model.joints[i] {
                    JointKind::Revolute { .. } | JointKind::Prismatic { .. } => out.push(q[iq]),
                    JointKind::Spherical => {
                        out.extend([q[iq + 3], q[iq], q[iq + 1], q[iq + 2]]);
                    }
                    JointKind::Free => {
                        out.extend(&q[iq..iq + 3]);
                        out.extend([q[iq + 6], q[iq + 3], q[iq + 4], q[iq + 5]]);
                    }
                    JointKind::Fixed => {}
                }
            }
        }
        stack.extend(group.children.iter().rev());
    }
    out
}

/// The up direction: −gravity, normalized; +z without gravity.
fn up_axis(gravity: &Vector3<f64>) -> Vector3<f64> {
    let n = gravity.norm();
    if n > 0.0 { -gravity / n } else { Vector3::z() }
}

/// A rotation taking +z to `up` (a unit vector): the plane's normal is its z.
fn rotation_z_to(up: &Vector3<f64>) -> Matrix3<f64> {
    UnitQuaternion::rotation_between(&Vector3::z(), up)
        .unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        })
        .to_rotation_matrix()
        .into_inner()
}

/// ` quat="w x y z"` for a rotation matrix; nothing for the identity.
fn quat_attr(rot: &Matrix3<f64>) -> String {
    if *rot == Matrix3::identity() {
        return String::new();
    }
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*rot));
    format!(" quat=\"{}\"", nums(&[q.w, q.i, q.j, q.k]))
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::model::ModelBuilder;
    use crate::spatial::{SpatialInertia, SpatialTransform};

    /// Three revolute bodies in a chain at one point, only the last with mass (one BVH joint of
    /// the euler model), under a link of inertia `diag`.
    fn chain(diag: [f64; 3]) -> Model {
        let mut b = ModelBuilder::new("chain", Vector3::new(0.0, 0.0, -9.81));
        let link = SpatialInertia::new(
            2.0,
            Vector3::new(0.0, 0.0, 0.1),
            Matrix3::from_diagonal(&Vector3::from(diag)),
        );
        let mut parent = 0;
        for (k, axis) in [Vector3::z(), Vector3::x(), Vector3::y()]
            .into_iter()
            .enumerate()
        {
            let name = format!("j.{k}");
            parent = b.add_body(
                parent,
                name.clone(),
                name,
                JointKind::Revolute { axis },
                if k == 0 {
                    SpatialTransform::from_translation(Vector3::new(0.0, 0.0, 1.0))
                } else {
                    SpatialTransform::IDENTITY
                },
                if k == 2 { link } else { SpatialInertia::ZERO },
            );
        }
        b.build()
    }

    #[test]
    fn massless_links_at_one_point_are_consecutive_joints_of_one_body() {
        let xml = model_to_mjcf(&chain([0.1, 0.1, 0.05]), &MjcfOptions::default()).unwrap();
        assert_eq!(xml.matches("<body ").count(), 1, "{xml}");
        assert_eq!(xml.matches("type=\"hinge\"").count(), 3);
        assert_eq!(xml.matches("<motor ").count(), 3);
        assert!(xml.contains("<body name=\"j\" pos=\"0 0 1\">"), "{xml}");
        assert!(!xml.contains("balanceinertia"));
    }

    #[test]
    fn inertia_mujoco_would_refuse_is_balanced_and_said() {
        // A + B < C: Corke's Stanford arm link 5 has a zero moment
        let xml = model_to_mjcf(&chain([0.003, 0.0, 0.0004]), &MjcfOptions::default()).unwrap();
        assert!(xml.contains("balanceinertia=\"true\""), "{xml}");
        assert!(xml.contains("<!-- j: principal moments"), "{xml}");
    }

    #[test]
    fn floor_normal_is_up() {
        for up in [Vector3::x(), Vector3::y(), Vector3::z(), -Vector3::z()] {
            let r = rotation_z_to(&up);
            assert!((r * Vector3::z() - up).norm() < 1e-15, "{up:?}");
        }
    }

    #[test]
    fn identity_rotation_writes_no_quaternion() {
        assert_eq!(quat_attr(&Matrix3::identity()), "");
        let r = rotation_z_to(&Vector3::y());
        assert!(quat_attr(&r).starts_with(" quat=\""));
    }
}
