//! The take flags as a front end receives them: which were given, which a command refuses
//! (a flag accepted and ignored is a bug), and the options a scene file and the flags make
//! together. The command line (`cli.rs`) and the Python module share this one path.

use super::{Flags, TakeOptions};
use crate::error::Error;
use crate::io::scene::Gains;
use std::path::Path;

/// The take flags each command leaves unused: giving one is an error that says so, never a
/// flag accepted and ignored (`simulate --contact feet` wrote the same bytes as without it).
/// A command not listed here uses every take flag.
pub const UNUSED_TAKE_FLAGS: &[(&str, &[&str], &str)] = &[
    (
        "info",
        &["--contact", "--damping"],
        "info describes the take and its model; ground forces and friction are for `id`",
    ),
    (
        "export positions",
        &[
            "--mass",
            "--sex",
            "--segments",
            "--link-mass",
            "--smooth",
            "--joints",
            "--contact",
            "--damping",
            "--lock",
        ],
        "positions come from the file's channels (those below the root welded at their mean \
         unless --joint-translations keep); no model, mass or smoothing enters",
    ),
    (
        "export states",
        &[
            "--mass",
            "--sex",
            "--segments",
            "--link-mass",
            "--contact",
            "--damping",
        ],
        "states are kinematics: no mass, contact or friction enters",
    ),
    (
        "export trc",
        &[
            "--mass",
            "--sex",
            "--segments",
            "--link-mass",
            "--smooth",
            "--joints",
            "--contact",
            "--damping",
            "--lock",
        ],
        "markers are the joints' positions from the file's channels (those below the root \
         welded at their mean unless --joint-translations keep); no model, mass or smoothing \
         enters",
    ),
    (
        "export gltf",
        &["--smooth", "--contact", "--damping"],
        "the animation is the file's channels (those below the root welded at their mean \
         unless --joint-translations keep), as `export trc` has them: no smoothing, contact or \
         friction enters",
    ),
    (
        "export grf",
        &["--damping"],
        "joint friction changes the joint torques, not what the ground gives",
    ),
    (
        "export urdf",
        &["--smooth", "--contact", "--damping", "--keep-first-frame"],
        "a URDF holds the model, not the motion",
    ),
    (
        "export mjcf",
        &["--smooth", "--contact", "--keep-first-frame"],
        "an MJCF holds the model, not the motion",
    ),
    (
        "simulate",
        &["--contact"],
        "the simulation has no ground contact model: the root residual carries the body \
         (`id --contact feet` estimates ground forces)",
    ),
    (
        "fd",
        &["--contact"],
        "forward dynamics applies the torques given; ground forces are estimated by `id`",
    ),
    (
        "mass-matrix",
        &["--contact"],
        "D(q) depends on the configuration alone",
    ),
    (
        "tradeoff",
        &["--contact"],
        "the trade-off simulations have no ground contact model",
    ),
    (
        "bench",
        &["--smooth", "--contact", "--keep-first-frame"],
        "bench times the dynamics of the model at sample states, not the take's motion",
    ),
    (
        "smooth",
        &[
            "--mass",
            "--sex",
            "--segments",
            "--link-mass",
            "--contact",
            "--damping",
        ],
        "smoothing writes the motion; no mass, contact or friction enters",
    ),
];

impl Flags<'_> {
    /// The take flags given, by their names on the command line (`--mass`, …).
    pub fn given(&self) -> Vec<&'static str> {
        [
            ("--unit", self.unit.is_some()),
            ("--stature", self.stature_m.is_some()),
            ("--up", self.up.is_some()),
            ("--positions", self.positions.is_some()),
            ("--subtree", self.subtree.is_some()),
            ("--mass", self.mass_kg.is_some()),
            ("--sex", self.sex.is_some()),
            ("--segments", self.segments.is_some()),
            ("--link-mass", !self.link_mass.is_empty()),
            ("--smooth", self.smooth.is_some()),
            ("--joints", self.joints.is_some()),
            ("--contact", self.contact.is_some()),
            ("--damping", !self.damping.is_empty()),
            ("--lock", !self.lock.is_empty()),
            ("--keep-first-frame", self.keep_first_frame),
            ("--joint-translations", self.joint_translations.is_some()),
        ]
        .into_iter()
        .filter_map(|(f, given)| given.then_some(f))
        .collect()
    }
}

/// Refuses a take flag in `given` that `command` (`id`, `export states`, …) would ignore
/// ([`UNUSED_TAKE_FLAGS`]); a command not listed there uses every take flag.
pub fn refuse_unused(command: &str, given: &[&str]) -> Result<(), Error> {
    let Some((_, unused, why)) = UNUSED_TAKE_FLAGS.iter().find(|(c, _, _)| *c == command) else {
        return Ok(());
    };
    if let Some(flag) = given.iter().find(|f| unused.contains(f)) {
        return Err(Error::Invalid(format!(
            "{flag} has no effect on `articula {command}`: {why}; remove it"
        )));
    }
    Ok(())
}

/// The take options of a scene file (if any) with the flags over them, and the scene's
/// computed-torque gains, reading the scene once.
pub fn options_from(
    scene: Option<&Path>,
    flags: &Flags,
) -> Result<(TakeOptions, Option<Gains>), Error> {
    let scene = scene.map(crate::io::scene::read).transpose()?;
    let mut o = match &scene {
        Some(s) => TakeOptions::from_scene(s)?,
        None => TakeOptions::default(),
    };
    o.apply_flags(flags)?;
    Ok((o, scene.and_then(|s| s.gains)))
}
