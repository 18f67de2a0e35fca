//! `articula info`: what a loaded take is — its skeleton, motion, unit and axes, the human
//! landmarks, the model and its masses, and the notes of what the loader assumed or changed.

use super::{Take, summary};
use crate::io::bvh::ResolvedPosition;
use crate::model::anthropometry::SegmentTable;

/// What `articula info` prints.
#[derive(Debug, Clone)]
pub struct Info<'a> {
    take: &'a Take,
}

/// Describes a loaded take.
pub fn info(take: &Take) -> Info<'_> {
    Info { take }
}

impl Info<'_> {
    /// The `--json` summary: the keys joints, frames, frame_time, nq, nv, scale_to_m,
    /// stature_m, up, gravity, mass_kg, unit, smooth (the smoothing applied), segments (the
    /// table of segment masses: `regression`, `fractions`, or `bone_volume` when no trunk is
    /// named), segments_stature_m (the stature the regression used, else null), human
    /// ([`Info::landmarks`]), contact (`feet` or `none`: what `--contact` gives the take,
    /// `auto` settled by [`resolve_contact`]), notes (a list of strings: what the pipeline
    /// assumed, changed or found, as `info` prints them) and skeleton (every joint: name,
    /// parent, channels, rotation_order, offset_m; [`summary::skeleton`]).
    ///
    /// [`resolve_contact`]: super::resolve_contact
    pub fn json(&self) -> serde_json::Value {
        let t = self.take;
        let regression = t.segments == Some(SegmentTable::Regression);
        serde_json::json!({
            "joints": t.bvh.joints.len(),
            "frames": t.bvh.frames,
            "frame_time": t.bvh.frame_time,
            "nq": t.model.nq,
            "nv": t.model.nv,
            "scale_to_m": t.scale_to_m,
            "stature_m": t.stature_m,
            "up": t.up.to_string(),
            "gravity": [t.model.gravity.x, t.model.gravity.y, t.model.gravity.z],
            "mass_kg": t.model.total_mass(),
            "unit": t.unit,
            "smooth": t.smooth.to_string(),
            "segments": t.segments.map_or("bone_volume".into(), |s| s.to_string()),
            "segments_stature_m": regression.then_some(t.stature_m),
            "human": self.landmarks(),
            "contact": t.options.contact.to_string(),
            "notes": t.notes,
            "skeleton": summary::skeleton(t),
        })
    }

    /// Which joints the skeleton's shape makes the pelvis, the legs' hip, knee and ankle, the
    /// lumbar joint, thorax and head, and the arms' shoulder, elbow and wrist; or why it is not
    /// a human's.
    pub fn landmarks(&self) -> String {
        let t = self.take;
        let name = |j: usize| t.bvh.joints[j].name.as_str();
        let h = match &t.human {
            Ok(h) => h,
            Err(why) => return format!("no ({why})"),
        };
        let mut s = format!("pelvis {}", name(h.pelvis));
        for (side, l) in ["left", "right"].iter().zip(&h.legs) {
            s += &format!(
                "; {side} leg {} / {} / {}",
                name(l.hip),
                name(l.knee),
                name(l.ankle)
            );
        }
        if let Some(sp) = &h.spine {
            s += &format!(
                "; lumbar {}, thorax {}, head {}",
                name(sp.lumbar),
                name(sp.thorax),
                name(sp.head)
            );
            for (side, a) in ["left", "right"].iter().zip(sp.arms.iter().flatten()) {
                s += &format!(
                    "; {side} arm {} / {} / {}",
                    name(a.shoulder),
                    name(a.elbow),
                    name(a.wrist)
                );
            }
        }
        s += if h.sides_from_names {
            " (sides from the names)"
        } else {
            " (sides from forward × up)"
        };
        s
    }

    /// The human-readable description.
    pub fn text(&self) -> String {
        use std::fmt::Write;
        let t = self.take;
        let b = &t.bvh;
        let mut s = String::new();
        let end_sites: usize = b.joints.iter().map(|j| j.end_sites.len()).sum();
        let _ = writeln!(s, "take        {}", t.path.display());
        let _ = writeln!(
            s,
            "skeleton    {} joints (root `{}`), {} End Sites, {} channels",
            b.joints.len(),
            b.joints.first().map(|j| j.name.as_str()).unwrap_or("?"),
            end_sites,
            b.channel_count
        );
        let _ = writeln!(
            s,
            "motion      {} frames, frame time {} s ({:.3} fps), {:.3} s",
            b.frames,
            b.frame_time,
            1.0 / b.frame_time,
            b.frames.saturating_sub(1) as f64 * b.frame_time
        );
        let _ = writeln!(
            s,
            "unit        {} (scale_to_m {}), stature {:.3} m, up {}",
            t.unit, t.scale_to_m, t.stature_m, t.up
        );
        let g = t.model.gravity;
        let _ = writeln!(s, "gravity     [{}, {}, {}] m/s²", g.x, g.y, g.z);
        let _ = writeln!(s, "human       {}", self.landmarks());
        let _ = writeln!(
            s,
            "model       {} joints, nq {}, nv {}, mass {:.3} kg, smoothing {}",
            t.options.joints,
            t.model.nq,
            t.model.nv,
            t.model.total_mass(),
            t.smooth
        );
        let _ = writeln!(s, "contact     {}", t.options.contact);
        let _ = match t.segments {
            Some(SegmentTable::Regression) => writeln!(
                s,
                "masses      segments: {} ({} kg, stature {:.3} m), rescaled to the body \
                 mass; radii of gyration: de Leva (1996) changed as the same regression of the \
                 moments of inertia changes them; centres of mass: de Leva (1996)",
                SegmentTable::Regression.source(),
                t.options.body.mass_kg,
                t.stature_m
            ),
            Some(table) => writeln!(
                s,
                "masses      segments: {}; centres of mass and radii of gyration: de Leva \
                 (1996)",
                table.source()
            ),
            None => writeln!(
                s,
                "masses      by bone volume (no joint name reads as a trunk)"
            ),
        };
        self.joints(&mut s);
        for n in &t.notes {
            let _ = writeln!(s, "note        {n}");
        }
        s
    }

    /// The `joints` lines of [`Info::text`]: each joint's channels, rotation order, position
    /// channels and whether they were welded.
    fn joints(&self, s: &mut String) {
        use std::fmt::Write;
        let t = self.take;
        let _ = writeln!(
            s,
            "joints      (name: channels [rotation order] position channels)"
        );
        for (i, (j, pos)) in t.bvh.joints.iter().zip(&t.positions).enumerate() {
            let chans: Vec<&str> = j.channels.iter().map(|c| c.name()).collect();
            let order = j
                .euler_order()
                .map(|o| format!(" [{o}]"))
                .unwrap_or_default();
            let p = match pos {
                ResolvedPosition::None => String::new(),
                ResolvedPosition::Add => " positions: add".into(),
                ResolvedPosition::Replace => " positions: replace".into(),
            };
            let held = match t.welded.iter().find(|w| w.joint == i) {
                Some(w) => format!(
                    ", welded at their mean (varied up to {})",
                    crate::motion::weld::centimetres(w.variation_m)
                ),
                None => String::new(),
            };
            let _ = writeln!(s, "  {}: {}{order}{p}{held}", j.name, chans.join(" "));
        }
    }
}
