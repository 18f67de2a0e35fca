//! Models from URDF, parsed with the `urdf-rs` crate (no hand-written XML parser).
//!
//! Supported joints: `revolute` and `continuous` (one angle, like Pinocchio's revolute but
//! `nq = 1`, where Pinocchio stores cos/sin for continuous joints), `prismatic`, `floating`
//! (a free joint) and `fixed` (the child link is merged into its parent's body, inertia
//! combined, as Pinocchio does). `planar` and `spherical` are rejected.
//!
//! Conventions (ROS REP 103 / the URDF spec): a joint's `<origin xyz rpy>` is the pose of the
//! child link frame in the parent link frame at q = 0, `rpy` being fixed-axis roll, pitch, yaw:
//! `R = Rz(yaw) · Ry(pitch) · Rx(roll)`; the `<axis>` is in the joint (child) frame and is
//! normalised; an `<inertial>` gives the COM at `origin.xyz` and the inertia tensor about the
//! COM in a frame rotated by `origin.rpy`. Joint limits and `<dynamics>` (damping, friction)
//! are not part of the rigid-body model and are ignored.
//!
//! The tree is visited depth first from the root link, children in file order; bodies are
//! named after their child links, coordinates after their joints. A fixed base welds the root
//! link to the world (its inertia is kept in the world's entry, unused by the dynamics); with
//! `floating` the root link hangs from a free joint named `root_joint` (Pinocchio's name).

use crate::error::Error;
use crate::model::{JointKind, Model, ModelBuilder};
use crate::rotation::{EulerOrder, euler_to_matrix};
use crate::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::path::Path;

/// How to read a URDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UrdfOptions {
    /// Give the root link a free joint (`root_joint`) instead of welding it to the world.
    pub floating: bool,
    /// Gravitational acceleration in the world frame (URDF has no field for it), m/s².
    pub gravity: Vector3<f64>,
}

impl Default for UrdfOptions {
    /// Fixed base, z up: gravity `[0, 0, −9.81]`.
    fn default() -> Self {
        Self {
            floating: false,
            gravity: Vector3::new(0.0, 0.0, -9.81),
        }
    }
}

/// Where a URDF link ended up in the model.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkFrame {
    /// The link's name.
    pub link: String,
    /// The body it is part of (0: welded to the world).
    pub body: usize,
    /// Pose of the link frame in that body's frame.
    pub pose: SpatialTransform,
}

/// The pose of a URDF `<origin xyz rpy>`.
pub fn pose(xyz: [f64; 3], rpy: [f64; 3]) -> SpatialTransform {
    SpatialTransform::new(
        euler_to_matrix(EulerOrder::ZYX, [rpy[2], rpy[1], rpy[0]]),
        Vector3::from(xyz),
    )
}

/// Reads a URDF file.
pub fn read_urdf(path: &Path, opts: &UrdfOptions) -> Result<Model, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_urdf(&text, path, opts)
}

/// Parses URDF text; `path` names the source in messages.
pub fn parse_urdf(text: &str, path: &Path, opts: &UrdfOptions) -> Result<Model, Error> {
    Ok(parse_urdf_links(text, path, opts)?.0)
}

/// 1-based line of the first `name="…"` attribute equal to `name` (for messages).
fn line_of(text: &str, name: &str) -> usize {
    let needle = format!("name=\"{name}\"");
    text.find(&needle)
        .map_or(1, |pos| text[..pos].matches('\n').count() + 1)
}

/// Parses URDF text and also returns where every link went (merged links included).
///
/// Errors: XML or URDF schema errors (from urdf-rs), no root or several root links, a joint
/// naming an unknown link, a link with two parents, unsupported joint types, a zero axis,
/// negative masses, non-finite numbers.
pub fn parse_urdf_links(
    text: &str,
    path: &Path,
    opts: &UrdfOptions,
) -> Result<(Model, Vec<LinkFrame>), Error> {
    let robot = urdf_rs::read_from_string(text)
        .map_err(|e| Error::parse(path, 1, 1, format!("not a valid URDF: {e}")))?;
    let at = |name: &str, message: String| Error::parse(path, line_of(text, name), 1, message);

    // the tree: parent link → joints (file order); every link but the root has one parent
    let link_index: HashMap<&str, usize> = robot
        .links
        .iter()
        .enumerate()
        .map(|(i, l)| (l.name.as_str(), i))
        .collect();
    let mut children: Vec<Vec<usize>> = vec![vec![]; robot.links.len()];
    let mut has_parent = vec![false; robot.links.len()];
    for (k, j) in robot.joints.iter().enumerate() {
        let p = *link_index.get(j.parent.link.as_str()).ok_or_else(|| {
            at(
                &j.name,
                format!(
                    "joint {:?}: unknown parent link {:?}",
                    j.name, j.parent.link
                ),
            )
        })?;
        let c = *link_index.get(j.child.link.as_str()).ok_or_else(|| {
            at(
                &j.name,
                format!("joint {:?}: unknown child link {:?}", j.name, j.child.link),
            )
        })?;
        if has_parent[c] {
            return Err(at(
                &j.name,
                format!(
                    "link {:?} has two parent joints (URDF is a tree)",
                    j.child.link
                ),
            ));
        }
        has_parent[c] = true;
        children[p].push(k);
    }
    let roots: Vec<usize> = (0..robot.links.len()).filter(|&i| !has_parent[i]).collect();
    let root = match roots.as_slice() {
        [r] => *r,
        [] => {
            return Err(Error::parse(
                path,
                1,
                1,
                "no root link: the joints form a loop",
            ));
        }
        many => {
            return Err(Error::parse(
                path,
                1,
                1,
                format!(
                    "{} root links ({}): a URDF has exactly one",
                    many.len(),
                    many.iter()
                        .map(|&i| robot.links[i].name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
    };

    // inertia of a link in its own frame
    let link_inertia = |i: usize| -> Result<SpatialInertia, Error> {
        let l = &robot.links[i];
        let inr = &l.inertial;
        let m = inr.mass.value;
        let t = &inr.inertia;
        let numbers = [m, t.ixx, t.ixy, t.ixz, t.iyy, t.iyz, t.izz]
            .into_iter()
            .chain(inr.origin.xyz.0)
            .chain(inr.origin.rpy.0);
        if numbers.into_iter().any(|x| !x.is_finite()) || m < 0.0 {
            return Err(at(
                &l.name,
                format!(
                    "link {:?}: the inertial needs a mass ≥ 0 and finite numbers",
                    l.name
                ),
            ));
        }
        let x = pose(inr.origin.xyz.0, inr.origin.rpy.0);
        let i_com = Matrix3::new(
            t.ixx, t.ixy, t.ixz, t.ixy, t.iyy, t.iyz, t.ixz, t.iyz, t.izz,
        );
        Ok(SpatialInertia::new(
            m,
            x.trans,
            x.rot * i_com * x.rot.transpose(),
        ))
    };

    let mut b = ModelBuilder::new(robot.name.clone(), opts.gravity);
    let mut frames: Vec<LinkFrame> = vec![];
    let mut world_inertia = SpatialInertia::ZERO;
    let root_body = if opts.floating {
        b.add_body(
            0,
            robot.links[root].name.clone(),
            "root_joint",
            JointKind::Free,
            SpatialTransform::IDENTITY,
            link_inertia(root)?,
        )
    } else {
        world_inertia = link_inertia(root)?;
        0
    };
    frames.push(LinkFrame {
        link: robot.links[root].name.clone(),
        body: root_body,
        pose: SpatialTransform::IDENTITY,
    });

    // depth first, children in file order: (joint, parent body, parent link pose in it)
    let mut stack: Vec<(usize, usize, SpatialTransform)> = children[root]
        .iter()
        .rev()
        .map(|&k| (k, root_body, SpatialTransform::IDENTITY))
        .collect();
    while let Some((k, body, x_body_link)) = stack.pop() {
        let j = &robot.joints[k];
        let c = link_index[j.child.link.as_str()];
        if !j
            .origin
            .xyz
            .0
            .iter()
            .chain(&j.origin.rpy.0)
            .all(|x| x.is_finite())
        {
            return Err(at(
                &j.name,
                format!("joint {:?}: non-finite origin", j.name),
            ));
        }
        let placement = x_body_link.compose(&pose(j.origin.xyz.0, j.origin.rpy.0));
        let axis = || -> Result<Vector3<f64>, Error> {
            let a = Vector3::from(j.axis.xyz.0);
            let n = a.norm();
            if !(n.is_finite() && n > 0.0) {
                return Err(at(
                    &j.name,
                    format!("joint {:?}: the axis must be non-zero", j.name),
                ));
            }
            Ok(a / n)
        };
        let kind = match j.joint_type {
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                JointKind::Revolute { axis: axis()? }
            }
            urdf_rs::JointType::Prismatic => JointKind::Prismatic { axis: axis()? },
            urdf_rs::JointType::Floating => JointKind::Free,
            urdf_rs::JointType::Fixed => JointKind::Fixed,
            ref other => {
                return Err(at(
                    &j.name,
                    format!(
                        "joint {:?}: type {other:?} is not supported (revolute, continuous, \
                         prismatic, floating, fixed)",
                        j.name
                    ),
                ));
            }
        };
        let inertia = link_inertia(c)?;
        let (child_body, x_child) = if kind == JointKind::Fixed {
            // merge the child link into this body
            let lumped = inertia.transformed(&placement);
            if body == 0 {
                world_inertia = world_inertia.add(&lumped);
            } else {
                let sum = b.model().inertia[body].add(&lumped);
                b.set_inertia(body, sum);
            }
            (body, placement)
        } else {
            let i = b.add_body(
                body,
                j.child.link.clone(),
                j.name.clone(),
                kind,
                placement,
                inertia,
            );
            (i, SpatialTransform::IDENTITY)
        };
        frames.push(LinkFrame {
            link: j.child.link.clone(),
            body: child_body,
            pose: x_child,
        });
        stack.extend(children[c].iter().rev().map(|&k| (k, child_body, x_child)));
    }
    let mut model = b.build();
    model.inertia[0] = world_inertia;
    Ok((model, frames))
}
