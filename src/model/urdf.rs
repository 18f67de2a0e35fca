//! Models from URDF, read with `roxmltree` (no hand-written XML parser, no recursion).
//!
//! roxmltree parses nested elements iteratively and stores the tree in flat vectors, so a
//! hostile file nested hundreds of thousands of elements deep neither overflows the stack nor
//! aborts (the `urdf-rs` crate used before recursed and aborted at 4,000 levels on a worker
//! thread). Only what the model needs is read: the robot's name, each link's `<inertial>` and
//! each joint's name, type, parent, child, origin and axis. Every other element (visual,
//! collision, material and its texture, gazebo, transmission …) is skipped whatever it
//! contains, so an empty `<texture/>` (iCub's and Romeo's URDFs) is fine. Errors name the file,
//! the line and column, and what was expected.
//!
//! Supported joints: `revolute` and `continuous` (one angle, like Pinocchio's revolute but
//! `nq = 1`, where Pinocchio stores cos/sin for continuous joints), `prismatic`, `floating`
//! (a free joint) and `fixed` (the child link is merged into its parent's body, inertia
//! combined, as Pinocchio does). `planar` and `spherical` are rejected.
//!
//! Conventions (ROS REP 103 / the URDF spec): a joint's `<origin xyz rpy>` is the pose of the
//! child link frame in the parent link frame at q = 0, `rpy` being fixed-axis roll, pitch, yaw:
//! `R = Rz(yaw) · Ry(pitch) · Rx(roll)`; from URDF 1.1 (`<robot version="1.1">`) an origin may
//! give `quat_xyzw` instead of `rpy` (converted as urdfdom does); the `<axis>` is in the joint
//! (child) frame and is normalised (default `1 0 0`); an `<inertial>` gives the COM at
//! `origin.xyz` and the inertia tensor about the COM in a frame rotated by `origin.rpy` (a link
//! without one is massless). Joint limits and `<dynamics>` (damping, friction) are not part of
//! the rigid-body model and are ignored.
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
use roxmltree::{Document, Node};
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

/// A `<link>`: what the model needs of it.
struct UrdfLink<'a> {
    name: &'a str,
    /// Byte offset of the element (for messages).
    at: usize,
    xyz: [f64; 3],
    rpy: [f64; 3],
    mass: f64,
    /// ixx, ixy, ixz, iyy, iyz, izz.
    inertia: [f64; 6],
}

/// A `<joint>`: what the model needs of it.
struct UrdfJoint<'a> {
    name: &'a str,
    at: usize,
    kind: &'a str,
    parent: &'a str,
    parent_at: usize,
    child: &'a str,
    child_at: usize,
    xyz: [f64; 3],
    rpy: [f64; 3],
    axis: [f64; 3],
    axis_at: usize,
}

/// Quotes a piece of the input for a message, shortened if long.
fn quoted(s: &str) -> String {
    const MAX: usize = 40;
    if s.chars().count() > MAX {
        format!("'{}…'", s.chars().take(MAX).collect::<String>())
    } else {
        format!("'{s}'")
    }
}

/// Roll, pitch, yaw of a quaternion (x, y, z, w), as urdfdom's `Rotation::getRPY`.
fn quaternion_to_rpy([x, y, z, w]: [f64; 4]) -> [f64; 3] {
    let norm = (x * x + y * y + z * z + w * w).sqrt();
    let [x, y, z, w] = if norm > 0.0 {
        [x / norm, y / norm, z / norm, w / norm]
    } else {
        [0.0, 0.0, 0.0, 1.0]
    };
    let sin_pitch = -2.0 * (x * z - w * y);
    if sin_pitch <= -0.99999 {
        [0.0, -std::f64::consts::FRAC_PI_2, 2.0 * x.atan2(-y)]
    } else if sin_pitch >= 0.99999 {
        [0.0, std::f64::consts::FRAC_PI_2, 2.0 * (-x).atan2(y)]
    } else {
        let (sqx, sqy, sqz, sqw) = (x * x, y * y, z * z, w * w);
        [
            (2.0 * (y * z + w * x)).atan2(sqw - sqx - sqy + sqz),
            sin_pitch.asin(),
            (2.0 * (x * y + w * z)).atan2(sqw + sqx - sqy - sqz),
        ]
    }
}

/// Reads elements and attributes, turning what is missing or malformed into located errors.
struct Reader<'d, 'input> {
    doc: &'d Document<'input>,
    path: &'d Path,
    /// URDF ≥ 1.1: `<origin quat_xyzw>` is read (urdfdom ignores it before).
    quaternions: bool,
}

impl<'d, 'input> Reader<'d, 'input> {
    /// An error at byte offset `pos` of the text.
    fn err(&self, pos: usize, message: impl Into<String>) -> Error {
        let p = self.doc.text_pos_at(pos);
        Error::parse(self.path, p.row as usize, p.col as usize, message)
    }

    /// The first child element named `tag`.
    fn child(node: Node<'d, 'input>, tag: &str) -> Option<Node<'d, 'input>> {
        node.children()
            .find(|c| c.is_element() && c.tag_name().name() == tag)
    }

    /// Byte offset of attribute `name`'s value (of the element if it has none).
    fn attr_at(node: Node<'d, 'input>, name: &str) -> usize {
        node.attribute_node(name)
            .map_or(node.range().start, |a| a.range_value().start)
    }

    /// A required attribute.
    fn attr(&self, node: Node<'d, 'input>, name: &str, what: &str) -> Result<&'d str, Error> {
        node.attribute(name).ok_or_else(|| {
            self.err(
                node.range().start,
                format!(
                    "{what}<{} {name}> is missing: expected a `{name}` attribute",
                    node.tag_name().name()
                ),
            )
        })
    }

    /// A required attribute holding one number.
    fn number(&self, node: Node<'d, 'input>, name: &str, what: &str) -> Result<f64, Error> {
        let v = self.attr(node, name, what)?;
        v.trim().parse::<f64>().map_err(|_| {
            self.err(
                Self::attr_at(node, name),
                format!(
                    "{what}<{} {name}> expects a number, found {}",
                    node.tag_name().name(),
                    quoted(v)
                ),
            )
        })
    }

    /// An optional attribute holding `N` numbers separated by blanks.
    fn numbers<const N: usize>(
        &self,
        node: Node<'d, 'input>,
        name: &str,
        what: &str,
    ) -> Result<Option<[f64; N]>, Error> {
        let Some(v) = node.attribute(name) else {
            return Ok(None);
        };
        let mut out = [0.0; N];
        let mut n = 0;
        for token in v.split_whitespace() {
            match token.parse::<f64>() {
                Ok(x) if n < N => out[n] = x,
                _ => {
                    n = N + 1;
                    break;
                }
            }
            n += 1;
        }
        if n != N {
            let count = ["", "one", "two", "three", "four"].get(N).unwrap_or(&"");
            return Err(self.err(
                Self::attr_at(node, name),
                format!(
                    "{what}<{} {name}> expects {count} numbers, found {}",
                    node.tag_name().name(),
                    quoted(v)
                ),
            ));
        }
        Ok(Some(out))
    }

    /// `(xyz, rpy)` of the `<origin>` child of `node` (zeros where absent).
    fn origin(&self, node: Node<'d, 'input>, what: &str) -> Result<([f64; 3], [f64; 3]), Error> {
        let Some(o) = Self::child(node, "origin") else {
            return Ok(([0.0; 3], [0.0; 3]));
        };
        let xyz = self.numbers::<3>(o, "xyz", what)?.unwrap_or_default();
        let mut rpy = self.numbers::<3>(o, "rpy", what)?;
        if self.quaternions
            && let Some(q) = self.numbers::<4>(o, "quat_xyzw", what)?
        {
            if rpy.is_some() {
                return Err(self.err(
                    o.range().start,
                    format!("{what}<origin> gives both rpy and quat_xyzw: keep one"),
                ));
            }
            rpy = Some(quaternion_to_rpy(q));
        }
        Ok((xyz, rpy.unwrap_or_default()))
    }

    fn link(&self, node: Node<'d, 'input>) -> Result<UrdfLink<'d>, Error> {
        let name = self.attr(node, "name", "")?;
        let what = format!("link `{name}`: ");
        let mut link = UrdfLink {
            name,
            at: node.range().start,
            xyz: [0.0; 3],
            rpy: [0.0; 3],
            mass: 0.0,
            inertia: [0.0; 6],
        };
        if let Some(inr) = Self::child(node, "inertial") {
            (link.xyz, link.rpy) = self.origin(inr, &what)?;
            let mass = Self::child(inr, "mass").ok_or_else(|| {
                self.err(
                    inr.range().start,
                    format!("{what}<inertial> has no <mass value>"),
                )
            })?;
            link.mass = self.number(mass, "value", &what)?;
            let t = Self::child(inr, "inertia").ok_or_else(|| {
                self.err(
                    inr.range().start,
                    format!("{what}<inertial> has no <inertia ixx ixy ixz iyy iyz izz>"),
                )
            })?;
            for (k, name) in ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]
                .into_iter()
                .enumerate()
            {
                link.inertia[k] = self.number(t, name, &what)?;
            }
        }
        Ok(link)
    }

    fn joint(&self, node: Node<'d, 'input>) -> Result<UrdfJoint<'d>, Error> {
        let name = self.attr(node, "name", "")?;
        let what = format!("joint `{name}`: ");
        let kind = self.attr(node, "type", &what)?;
        if ![
            "revolute",
            "continuous",
            "prismatic",
            "floating",
            "fixed",
            "planar",
            "spherical",
        ]
        .contains(&kind)
        {
            return Err(self.err(
                Self::attr_at(node, "type"),
                format!(
                    "{what}unknown type {} (revolute, continuous, prismatic, floating, fixed)",
                    quoted(kind)
                ),
            ));
        }
        let end = |tag: &str| -> Result<(&'d str, usize), Error> {
            let e = Self::child(node, tag).ok_or_else(|| {
                self.err(node.range().start, format!("{what}no <{tag} link> element"))
            })?;
            Ok((self.attr(e, "link", &what)?, e.range().start))
        };
        let (parent, parent_at) = end("parent")?;
        let (child, child_at) = end("child")?;
        let (xyz, rpy) = self.origin(node, &what)?;
        let (axis, axis_at) = match Self::child(node, "axis") {
            Some(a) => (
                self.numbers::<3>(a, "xyz", &what)?.ok_or_else(|| {
                    self.err(a.range().start, format!("{what}<axis> needs an xyz"))
                })?,
                a.range().start,
            ),
            None => ([1.0, 0.0, 0.0], node.range().start),
        };
        Ok(UrdfJoint {
            name,
            at: node.range().start,
            kind,
            parent,
            parent_at,
            child,
            child_at,
            xyz,
            rpy,
            axis,
            axis_at,
        })
    }
}

/// Parses URDF text and also returns where every link went (merged links included).
///
/// Errors (all [`Error::Parse`], with the line and column): text that is not well-formed XML,
/// a root element other than `<robot>`, a missing or malformed attribute the model needs, a
/// link defined twice, a joint naming an undefined link, a link with two parents, no root or
/// several root links, links the root does not reach, unsupported joint types, a zero axis,
/// negative masses, non-finite numbers.
pub fn parse_urdf_links(
    text: &str,
    path: &Path,
    opts: &UrdfOptions,
) -> Result<(Model, Vec<LinkFrame>), Error> {
    let doc = Document::parse(text).map_err(|e| {
        use roxmltree::Error as X;
        let truncated = match e {
            X::UnexpectedEndOfStream => Some("the text ends inside a tag"),
            X::UnclosedRootNode => Some("the root element is never closed"),
            _ => None,
        };
        if let Some(what) = truncated {
            // these carry no position: point at the end of the text
            let last = text.rfind('\n').map_or(0, |i| i + 1);
            Error::parse(
                path,
                text.matches('\n').count() + 1,
                text[last..].chars().count() + 1,
                format!("not well-formed XML: {what} (truncated file?)"),
            )
        } else {
            let p = e.pos();
            let message = format!("not well-formed XML: {e}");
            Error::parse(path, p.row as usize, p.col as usize, message)
        }
    })?;
    let robot = doc.root_element();
    let version = robot
        .attribute("version")
        .and_then(|v| {
            let (major, minor) = v.trim().split_once('.')?;
            Some((major.parse::<u32>().ok()?, minor.parse::<u32>().ok()?))
        })
        .unwrap_or((1, 0));
    let r = Reader {
        doc: &doc,
        path,
        quaternions: version >= (1, 1),
    };
    if robot.tag_name().name() != "robot" {
        return Err(r.err(
            robot.range().start,
            format!(
                "expected a <robot> root element, found <{}>",
                robot.tag_name().name()
            ),
        ));
    }
    let mut links: Vec<UrdfLink> = vec![];
    let mut joints: Vec<UrdfJoint> = vec![];
    for node in robot.children().filter(|n| n.is_element()) {
        match node.tag_name().name() {
            "link" => links.push(r.link(node)?),
            "joint" => joints.push(r.joint(node)?),
            _ => {}
        }
    }

    // the tree: parent link → joints (file order); every link but the root has one parent
    let mut link_index: HashMap<&str, usize> = HashMap::with_capacity(links.len());
    for (i, l) in links.iter().enumerate() {
        if link_index.insert(l.name, i).is_some() {
            return Err(r.err(l.at, format!("link `{}` is defined twice", l.name)));
        }
    }
    let mut children: Vec<Vec<usize>> = vec![vec![]; links.len()];
    let mut has_parent = vec![false; links.len()];
    for (k, j) in joints.iter().enumerate() {
        let p = *link_index.get(j.parent).ok_or_else(|| {
            r.err(
                j.parent_at,
                format!(
                    "joint `{}` names parent link `{}`, which is not defined",
                    j.name, j.parent
                ),
            )
        })?;
        let c = *link_index.get(j.child).ok_or_else(|| {
            r.err(
                j.child_at,
                format!(
                    "joint `{}` names child link `{}`, which is not defined",
                    j.name, j.child
                ),
            )
        })?;
        if has_parent[c] {
            return Err(r.err(
                j.child_at,
                format!(
                    "joint `{}`: link `{}` already has a parent joint (URDF is a tree)",
                    j.name, j.child
                ),
            ));
        }
        has_parent[c] = true;
        children[p].push(k);
    }
    let roots: Vec<usize> = (0..links.len()).filter(|&i| !has_parent[i]).collect();
    let root = match roots.as_slice() {
        [r] => *r,
        [] if links.is_empty() => {
            return Err(r.err(robot.range().start, "the robot has no <link>"));
        }
        [] => {
            return Err(r.err(robot.range().start, "no root link: the joints form a loop"));
        }
        many => {
            return Err(r.err(
                links[many[1]].at,
                format!(
                    "{} root links ({}): a URDF has exactly one",
                    many.len(),
                    many.iter()
                        .map(|&i| links[i].name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
    };

    // inertia of a link in its own frame
    let link_inertia = |i: usize| -> Result<SpatialInertia, Error> {
        let l = &links[i];
        let m = l.mass;
        let [ixx, ixy, ixz, iyy, iyz, izz] = l.inertia;
        let numbers = [m, ixx, ixy, ixz, iyy, iyz, izz]
            .into_iter()
            .chain(l.xyz)
            .chain(l.rpy);
        if numbers.into_iter().any(|x| !x.is_finite()) || m < 0.0 {
            return Err(r.err(
                l.at,
                format!(
                    "link `{}`: the inertial needs a mass ≥ 0 and finite numbers",
                    l.name
                ),
            ));
        }
        let x = pose(l.xyz, l.rpy);
        let i_com = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
        Ok(SpatialInertia::new(
            m,
            x.trans,
            x.rot * i_com * x.rot.transpose(),
        ))
    };

    let name = robot.attribute("name").unwrap_or_default();
    let mut b = ModelBuilder::new(name.to_string(), opts.gravity);
    let mut frames: Vec<LinkFrame> = vec![];
    let mut world_inertia = SpatialInertia::ZERO;
    let root_body = if opts.floating {
        b.add_body(
            0,
            links[root].name.to_string(),
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
        link: links[root].name.to_string(),
        body: root_body,
        pose: SpatialTransform::IDENTITY,
    });

    // depth first, children in file order: (joint, parent body, parent link pose in it)
    let mut reached = vec![false; links.len()];
    reached[root] = true;
    let mut stack: Vec<(usize, usize, SpatialTransform)> = children[root]
        .iter()
        .rev()
        .map(|&k| (k, root_body, SpatialTransform::IDENTITY))
        .collect();
    while let Some((k, body, x_body_link)) = stack.pop() {
        let j = &joints[k];
        let c = link_index[j.child];
        reached[c] = true;
        if !j.xyz.iter().chain(&j.rpy).all(|x| x.is_finite()) {
            return Err(r.err(j.at, format!("joint `{}`: non-finite origin", j.name)));
        }
        let placement = x_body_link.compose(&pose(j.xyz, j.rpy));
        let axis = || -> Result<Vector3<f64>, Error> {
            let a = Vector3::from(j.axis);
            let n = a.norm();
            if !(n.is_finite() && n > 0.0) {
                return Err(r.err(
                    j.axis_at,
                    format!("joint `{}`: the axis must be non-zero", j.name),
                ));
            }
            Ok(a / n)
        };
        let kind = match j.kind {
            "revolute" | "continuous" => JointKind::Revolute { axis: axis()? },
            "prismatic" => JointKind::Prismatic { axis: axis()? },
            "floating" => JointKind::Free,
            "fixed" => JointKind::Fixed,
            other => {
                return Err(r.err(
                    j.at,
                    format!(
                        "joint `{}`: type {other} is not supported (revolute, continuous, \
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
                j.child.to_string(),
                j.name.to_string(),
                kind,
                placement,
                inertia,
            );
            (i, SpatialTransform::IDENTITY)
        };
        frames.push(LinkFrame {
            link: j.child.to_string(),
            body: child_body,
            pose: x_child,
        });
        stack.extend(children[c].iter().rev().map(|&k| (k, child_body, x_child)));
    }
    if let Some(lost) = reached.iter().position(|&seen| !seen) {
        // every link has at most one parent and only the root has none: the rest hang in loops
        return Err(r.err(
            links[lost].at,
            format!(
                "link `{}` is not reached from the root link `{}`: the joints form a loop",
                links[lost].name, links[root].name
            ),
        ));
    }
    let mut model = b.build();
    model.inertia[0] = world_inertia;
    Ok((model, frames))
}
