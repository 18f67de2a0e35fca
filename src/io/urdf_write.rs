//! A [`Model`] as URDF text, for checking articula's models in other tools (Pinocchio, MuJoCo).
//!
//! Layout: the root link `world`; one link per body, named as the body; one joint per body,
//! named as its coordinates (`LeftUpLeg.Zrotation` in a BVH euler model), with
//! `<origin>` = the body's placement (`rpy` = fixed-axis roll, pitch, yaw,
//! `R = Rz(y)·Ry(p)·Rx(r)`), `<axis>` = the joint axis; revolute/prismatic joints get
//! `<limit lower="-1000" upper="1000" effort="1e6" velocity="1e6"/>` because URDF requires
//! limits on them and a model has none (Pinocchio and MuJoCo only use them as bounds, and BVH
//! angles may be unwrapped past ±2π); free joints are `floating`; spherical joints have no URDF
//! type and are rejected (export the euler joint model). Links carry `<inertial>` with the COM
//! as origin (no rotation) when they have mass; massless (fictitious) links carry none, which
//! Pinocchio reads as zero inertia. A link with a drawing shape has it as `<visual>` and
//! `<collision>` geometry (a sphere, or a cylinder along the shape's long axis: URDF has no
//! ellipsoid). Gravity is not part of URDF: it is written in the header comment and in
//! MuJoCo's extension, `<mujoco><option gravity="…"/></mujoco>`, which MuJoCo's URDF import reads
//! (URDF parsers ignore the element). In the same element, MuJoCo's compiler gets
//! `boundmass`/`boundinertia` (it rejects moving massless bodies: they get 1e-9 kg /
//! 1e-12 kg·m²) and `inertiafromgeom="false"` (the geometry adds no mass). MuJoCo's URDF import
//! lets every collision geometry touch every other (but a parent's): simulate with the MJCF
//! export instead (`io::mjcf_write`). Numbers are printed in their shortest exact form (`io::shortest`), so reading
//! the file back ([`read_urdf`](crate::model::urdf::read_urdf), fixed base) gives the same model.

use crate::error::Error;
use crate::io::xml::{attr, comment, num, vec3};
use crate::model::{JointKind, Model, Superquadric};
use crate::rotation::{EulerOrder, matrix_to_euler};
use crate::spatial::SpatialInertia;
use std::fmt::Write;

/// `<inertial>`: the centre of mass as origin (no rotation), mass, inertia about the COM.
fn write_inertial(w: &mut String, inertia: &SpatialInertia) {
    let c = &inertia.inertia_com;
    let _ = writeln!(w, "    <inertial>");
    let _ = writeln!(
        w,
        "      <origin xyz=\"{}\" rpy=\"0 0 0\"/>",
        vec3(&inertia.com)
    );
    let _ = writeln!(w, "      <mass value=\"{}\"/>", num(inertia.mass));
    let _ = writeln!(
        w,
        "      <inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/>",
        num(c[(0, 0)]),
        num(c[(0, 1)]),
        num(c[(0, 2)]),
        num(c[(1, 1)]),
        num(c[(1, 2)]),
        num(c[(2, 2)])
    );
    let _ = writeln!(w, "    </inertial>");
}

/// A link's drawing shape as URDF geometry, with its `<origin>`: a sphere when the semi-axes
/// are equal, else a cylinder along the shape's long (local z) axis, its radius the geometric
/// mean of the two short semi-axes and its length the long axis (URDF has no ellipsoid).
/// `None` for a shape with a semi-axis that is not positive.
fn geometry(s: &Superquadric) -> Option<(String, String)> {
    let [a, b, c] = [s.size.x, s.size.y, s.size.z];
    if ![a, b, c].iter().all(|&x| x.is_finite() && x > 0.0) {
        return None;
    }
    let [yaw, pitch, roll] = matrix_to_euler(EulerOrder::ZYX, &s.rot);
    let origin = format!(
        "<origin xyz=\"{}\" rpy=\"{} {} {}\"/>",
        vec3(&s.center),
        num(roll),
        num(pitch),
        num(yaw)
    );
    let geometry = if a == b && b == c {
        format!("<sphere radius=\"{}\"/>", num(a))
    } else {
        format!(
            "<cylinder radius=\"{}\" length=\"{}\"/>",
            num((a * b).sqrt()),
            num(2.0 * c)
        )
    };
    Some((origin, geometry))
}

/// The URDF text of `model` (see the module doc).
///
/// Errors: a spherical joint (no URDF equivalent), or two bodies with the same name.
pub fn model_to_urdf(model: &Model) -> Result<String, Error> {
    let mut names = std::collections::HashSet::new();
    for n in &model.body_names {
        if !names.insert(n.as_str()) {
            return Err(Error::Invalid(format!(
                "two bodies are named {n:?}: URDF link names must be unique"
            )));
        }
    }
    let g = &model.gravity;
    let mut out = String::new();
    let w = &mut out;
    // writing to a String cannot fail
    let _ = writeln!(w, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        w,
        "<!-- {} as URDF, written by articula: {} bodies, nq = {}, nv = {}, total mass {} kg.\n     \
         gravity (world frame, m/s^2): {} {} {}\n     \
         SI units; one joint per coordinate; massless links have no inertial. -->",
        comment(&model.name),
        model.nbodies() - 1,
        model.nq,
        model.nv,
        num(model.total_mass()),
        num(g.x),
        num(g.y),
        num(g.z)
    );
    let _ = writeln!(w, "<robot name=\"{}\">", attr(&model.name));
    let _ = writeln!(
        w,
        "  <mujoco><compiler boundmass=\"1e-9\" boundinertia=\"1e-12\" inertiafromgeom=\"false\"/>\
         <option gravity=\"{}\"/></mujoco>",
        vec3(g)
    );
    for i in 0..model.nbodies() {
        let link = &model.body_names[i];
        let inertia = &model.inertia[i];
        let massive = inertia.mass > 0.0 || inertia.inertia_com.abs().max() > 0.0;
        let shape = model.shapes[i].as_ref().and_then(geometry);
        if !massive && shape.is_none() {
            let _ = writeln!(w, "  <link name=\"{}\"/>", attr(link));
        } else {
            let _ = writeln!(w, "  <link name=\"{}\">", attr(link));
            if massive {
                write_inertial(w, inertia);
            }
            if let Some((origin, geometry)) = shape {
                for tag in ["visual", "collision"] {
                    let _ = writeln!(w, "    <{tag}>");
                    let _ = writeln!(w, "      {origin}");
                    let _ = writeln!(w, "      <geometry>{geometry}</geometry>");
                    let _ = writeln!(w, "    </{tag}>");
                }
            }
            let _ = writeln!(w, "  </link>");
        }
        if i == 0 {
            continue;
        }
        let (kind, axis) = match model.joints[i] {
            JointKind::Revolute { axis } => ("revolute", Some(axis)),
            JointKind::Prismatic { axis } => ("prismatic", Some(axis)),
            JointKind::Free => ("floating", None),
            JointKind::Fixed => ("fixed", None),
            JointKind::Spherical => {
                return Err(Error::Invalid(format!(
                    "joint {:?} is spherical, which URDF cannot express: export the euler \
                     joint model (--joints euler)",
                    model.joint_names[i]
                )));
            }
        };
        let x = &model.placement[i];
        let [yaw, pitch, roll] = matrix_to_euler(EulerOrder::ZYX, &x.rot);
        let _ = writeln!(
            w,
            "  <joint name=\"{}\" type=\"{kind}\">",
            attr(&model.joint_names[i])
        );
        let _ = writeln!(
            w,
            "    <parent link=\"{}\"/>",
            attr(&model.body_names[model.parent[i]])
        );
        let _ = writeln!(w, "    <child link=\"{}\"/>", attr(link));
        let _ = writeln!(
            w,
            "    <origin xyz=\"{}\" rpy=\"{} {} {}\"/>",
            vec3(&x.trans),
            num(roll),
            num(pitch),
            num(yaw)
        );
        if let Some(a) = axis {
            let _ = writeln!(w, "    <axis xyz=\"{}\"/>", vec3(&a));
            let _ = writeln!(
                w,
                "    <limit lower=\"-1000\" upper=\"1000\" effort=\"1e6\" velocity=\"1e6\"/>"
            );
        }
        let _ = writeln!(w, "  </joint>");
    }
    let _ = writeln!(w, "</robot>");
    Ok(out)
}
