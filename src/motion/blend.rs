//! Blending and warping takes (the paper's section 4): two takes of the same skeleton joined
//! through a transition window, several takes chained through several windows.
//!
//! Through the window `[t0, t1]` the result is `θr(t) = θa(t)(1 − λ) + θb(t)λ` with
//! `λ = ramp((t − t0)/(t1 − t0))`; before the window it is take a, after it take b. Done right:
//! - λ is the C² quintic of [`super::ramp`] by default: inverse dynamics uses q̈, and a linear
//!   (C⁰) ramp would give q̇ a jump and q̈ a spike at each window edge;
//! - rotations are blended per joint on the rotation group, by slerp along the shortest arc
//!   (Shoemake 1985, *Animating rotation with quaternion curves*, SIGGRAPH), not channel by
//!   channel: the joint's rotation channels become a quaternion (`rotation::euler_to_matrix`),
//!   and the blended rotation becomes channels again with `rotation::matrix_to_euler_near`, the
//!   triple nearest to the previous output frame, so the written channels stay continuous;
//! - positions (root translation, position channels of any joint) are blended linearly;
//! - take b can be re-timed, `t_b = offset + scale·t` ([`TimeMap`]), so that gait phases line
//!   up, and is resampled at take a's frame times (linear interpolation of positions, slerp of
//!   rotations), so the two takes may have different frame rates;
//! - take b's root can be aligned to take a at the window start ([`Align`]): its heading (yaw
//!   about the up axis) is turned to a's, and its ground-plane position moved onto a's, for the
//!   whole of b (b's height is kept: the floor does not move).
//!
//! Everything here works on the plain BVH description, in the files' own units (lengths as
//! written, angles in degrees at the edges, radians inside the rotation math); the output has
//! take a's skeleton (its offsets), frame time and time origin, and runs until take b ends.
//! Joints whose rotation channels are not three distinct axes (one or two channels) are blended
//! angle by angle, b's angle taken to the turn nearest a's.

use super::derive::{quat_exp, quat_log};
use super::ramp::RampShape;
use crate::error::Error;
use crate::io::bvh::{Bvh, Channel};
use crate::rotation::{EulerOrder, axis_rotation, euler_to_matrix, matrix_to_euler_near};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use std::fmt;
use std::str::FromStr;

/// A transition window `[t0, t1]` (s, on take a's clock, i.e. the output's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WarpWindow {
    /// Start of the transition (s): the output is take a up to here.
    pub t0: f64,
    /// End of the transition (s): the output is take b from here on.
    pub t1: f64,
}

impl FromStr for WarpWindow {
    type Err = Error;
    /// `T0:T1` in seconds, e.g. `2.0:2.6`, with `0 ≤ T0 < T1`.
    fn from_str(s: &str) -> Result<Self, Error> {
        let bad = |why: &str| {
            Error::Invalid(format!(
                "window `{s}`: {why}; expected `T0:T1` in seconds with 0 ≤ T0 < T1, e.g. `2.0:2.6`"
            ))
        };
        let (a, b) = s.trim().split_once(':').ok_or_else(|| bad("missing `:`"))?;
        let num = |x: &str| {
            x.trim()
                .strip_suffix('s')
                .unwrap_or(x.trim())
                .parse::<f64>()
                .map_err(|_| bad(&format!("`{x}` is not a time")))
        };
        let w = WarpWindow {
            t0: num(a)?,
            t1: num(b)?,
        };
        if !(w.t0.is_finite() && w.t1.is_finite() && w.t0 >= 0.0 && w.t0 < w.t1) {
            return Err(bad("the start must be ≥ 0 and before the end"));
        }
        Ok(w)
    }
}

impl fmt::Display for WarpWindow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.t0, self.t1)
    }
}

/// What of take b's root is aligned to take a at the window start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Align {
    /// Move b's root so that its ground-plane position at `t0` is a's (height kept).
    pub root: bool,
    /// Turn b about the up axis so that its root heading at `t0` is a's.
    pub heading: bool,
}

impl Align {
    /// No alignment.
    pub const NONE: Align = Align {
        root: false,
        heading: false,
    };
    /// Root position and heading.
    pub const ALL: Align = Align {
        root: true,
        heading: true,
    };
}

impl FromStr for Align {
    type Err = Error;
    /// `none`, or a comma-separated list of `root`, `heading` (e.g. `root,heading`).
    fn from_str(s: &str) -> Result<Self, Error> {
        let mut a = Align::NONE;
        let t = s.trim().to_ascii_lowercase();
        if t == "none" {
            return Ok(a);
        }
        for part in t.split(',') {
            match part.trim() {
                "root" => a.root = true,
                "heading" => a.heading = true,
                other => {
                    return Err(Error::Invalid(format!(
                        "alignment `{s}`: unknown item `{other}`; expected `none` or a \
                         comma-separated list of `root`, `heading` (e.g. `root,heading`)"
                    )));
                }
            }
        }
        Ok(a)
    }
}

impl fmt::Display for Align {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.root, self.heading) {
            (false, false) => write!(f, "none"),
            (true, false) => write!(f, "root"),
            (false, true) => write!(f, "heading"),
            (true, true) => write!(f, "root,heading"),
        }
    }
}

/// Re-timing of take b: at output time `t` (s), take b is sampled at `t_b = offset + scale·t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeMap {
    /// Time of take b at output time 0 (s).
    pub offset: f64,
    /// Seconds of take b per output second (> 0; 1 keeps b's speed, 0.5 plays it at half speed).
    pub scale: f64,
}

impl TimeMap {
    /// `t_b = t`.
    pub const IDENTITY: TimeMap = TimeMap {
        offset: 0.0,
        scale: 1.0,
    };
    /// Take b's time at output time `t`.
    pub fn apply(&self, t: f64) -> f64 {
        self.offset + self.scale * t
    }
}

impl Default for TimeMap {
    fn default() -> Self {
        TimeMap::IDENTITY
    }
}

impl FromStr for TimeMap {
    type Err = Error;
    /// `OFFSET` or `OFFSET:SCALE` (s, and seconds of b per output second), e.g. `0.35:1.1`.
    fn from_str(s: &str) -> Result<Self, Error> {
        let bad = |why: &str| {
            Error::Invalid(format!(
                "time map `{s}`: {why}; expected `OFFSET` or `OFFSET:SCALE` (take b is sampled at \
                 OFFSET + SCALE·t seconds, SCALE > 0), e.g. `0.35:1.1`"
            ))
        };
        let mut parts = s.trim().split(':');
        let num = |x: &str| {
            x.trim()
                .parse::<f64>()
                .map_err(|_| bad(&format!("`{x}` is not a number")))
        };
        let offset = num(parts.next().unwrap_or(""))?;
        let scale = match parts.next() {
            Some(x) => num(x)?,
            None => 1.0,
        };
        if parts.next().is_some() {
            return Err(bad("too many `:` fields"));
        }
        if !(offset.is_finite() && scale.is_finite() && scale > 0.0) {
            return Err(bad("the offset must be finite and the scale positive"));
        }
        Ok(TimeMap { offset, scale })
    }
}

/// How to blend, besides the window and the time map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlendOptions {
    /// What of take b's root to align to take a at the window start.
    pub align: Align,
    /// The vertical axis of the takes (0 = X, 1 = Y, 2 = Z): heading is the yaw about it and the
    /// ground plane is orthogonal to it.
    pub up_axis: usize,
    /// The ramp λ; [`RampShape::Quintic`] (C²) unless comparing.
    pub ramp: RampShape,
}

impl Default for BlendOptions {
    fn default() -> Self {
        BlendOptions {
            align: Align::NONE,
            up_axis: 1,
            ramp: RampShape::Quintic,
        }
    }
}

/// Refuses two takes whose skeletons differ: same joints in the same order with the same names,
/// parents and channels. Bone lengths (OFFSETs) may differ (two actors): the blend keeps take
/// a's. The message names the first joint that differs.
pub fn check_same_skeleton(a: &Bvh, b: &Bvh) -> Result<(), Error> {
    let differ = |what: String| {
        Err(Error::Invalid(format!(
            "the takes have different skeletons: {what}; blending needs the same joints, \
             hierarchy and channels"
        )))
    };
    let parent_name = |t: &Bvh, p: Option<usize>| match p {
        Some(p) => format!("`{}`", t.joints[p].name),
        None => "none (root)".to_string(),
    };
    let channels = |c: &[Channel]| c.iter().map(|c| c.name()).collect::<Vec<_>>().join(" ");
    for (i, (ja, jb)) in a.joints.iter().zip(&b.joints).enumerate() {
        if ja.name != jb.name {
            return differ(format!(
                "joint {} is `{}` in take a but `{}` in take b",
                i + 1,
                ja.name,
                jb.name
            ));
        }
        if ja.parent.map(|p| &a.joints[p].name) != jb.parent.map(|p| &b.joints[p].name) {
            return differ(format!(
                "joint `{}` has parent {} in take a but {} in take b",
                ja.name,
                parent_name(a, ja.parent),
                parent_name(b, jb.parent)
            ));
        }
        if ja.channels != jb.channels {
            return differ(format!(
                "joint `{}` has channels `{}` in take a but `{}` in take b",
                ja.name,
                channels(&ja.channels),
                channels(&jb.channels)
            ));
        }
    }
    if a.joints.len() != b.joints.len() {
        let (longer, which) = if a.joints.len() > b.joints.len() {
            (a, "a")
        } else {
            (b, "b")
        };
        let extra = &longer.joints[a.joints.len().min(b.joints.len())];
        return differ(format!(
            "joint `{}` is only in take {which} (take a has {} joints, take b {})",
            extra.name,
            a.joints.len(),
            b.joints.len()
        ));
    }
    Ok(())
}

/// How the channels of one joint are blended.
#[derive(Debug, Clone)]
enum RotPlan {
    /// No rotation channels.
    None,
    /// Three distinct rotation axes: columns of the channels in application order.
    Euler { order: EulerOrder, cols: [usize; 3] },
    /// Any other set of rotation channels: blended angle by angle.
    Angles { cols: Vec<usize> },
}

/// The per-joint layout of a frame row, computed once.
#[derive(Debug, Clone)]
struct Plan {
    /// Rotation plan of each joint.
    rot: Vec<RotPlan>,
    /// Columns of every position channel (any joint).
    pos: Vec<usize>,
    /// Columns of the root's X, Y, Z position channels.
    root_pos: [Option<usize>; 3],
}

impl Plan {
    fn new(t: &Bvh) -> Plan {
        let mut rot = Vec::with_capacity(t.joints.len());
        let mut pos = vec![];
        for j in &t.joints {
            let mut rcols = vec![];
            let mut axes = vec![];
            for (c, ch) in j.channels.iter().enumerate() {
                let col = j.first_channel + c;
                if ch.is_rotation() {
                    rcols.push(col);
                    axes.push(ch.axis());
                } else {
                    pos.push(col);
                }
            }
            let order = (axes.len() == 3)
                .then(|| EulerOrder::from_axes([axes[0], axes[1], axes[2]]))
                .flatten();
            rot.push(match order {
                _ if rcols.is_empty() => RotPlan::None,
                Some(order) => RotPlan::Euler {
                    order,
                    cols: [rcols[0], rcols[1], rcols[2]],
                },
                None => RotPlan::Angles { cols: rcols },
            });
        }
        let mut root_pos = [None; 3];
        if let Some(root) = t.joints.first() {
            for (c, ch) in root.channels.iter().enumerate() {
                if !ch.is_rotation() {
                    root_pos[ch.axis()] = Some(root.first_channel + c);
                }
            }
        }
        Plan { rot, pos, root_pos }
    }
}

fn rad(deg: f64) -> f64 {
    deg.to_radians()
}

/// The rotation of an Euler joint in frame row `row`.
fn euler_quat(row: &[f64], order: EulerOrder, cols: &[usize; 3]) -> UnitQuaternion<f64> {
    let m = euler_to_matrix(
        order,
        [rad(row[cols[0]]), rad(row[cols[1]]), rad(row[cols[2]])],
    );
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// Slerp from `a` to `b` along the shortest arc: `a · exp(λ · log(a⁻¹ b))`.
fn slerp_shortest(
    a: &UnitQuaternion<f64>,
    b: &UnitQuaternion<f64>,
    lambda: f64,
) -> UnitQuaternion<f64> {
    a * quat_exp(&(quat_log(&(a.inverse() * b)) * lambda))
}

/// `b` shifted by whole turns (degrees) to lie within half a turn of `a`.
fn nearest_turn_deg(b: f64, a: f64) -> f64 {
    b + 360.0 * ((a - b) / 360.0).round()
}

/// A take sampled at a fractional frame, between two rows.
struct Sample<'t> {
    r0: &'t [f64],
    r1: &'t [f64],
    /// Fraction of the way from `r0` to `r1`, in `[0, 1]`.
    f: f64,
}

impl<'t> Sample<'t> {
    /// Take `t` at time `time` (s), clamped to the take.
    fn at(t: &'t Bvh, time: f64) -> Sample<'t> {
        let u = (time / t.frame_time).clamp(0.0, (t.frames - 1) as f64);
        let i = (u.floor() as usize).min(t.frames - 1);
        let j = (i + 1).min(t.frames - 1);
        Sample {
            r0: t.frame(i),
            r1: t.frame(j),
            f: u - i as f64,
        }
    }
    fn value(&self, col: usize) -> f64 {
        self.r0[col] + self.f * (self.r1[col] - self.r0[col])
    }
    fn angle(&self, col: usize) -> f64 {
        let a = self.r0[col];
        a + self.f * (nearest_turn_deg(self.r1[col], a) - a)
    }
    fn quat(&self, order: EulerOrder, cols: &[usize; 3]) -> UnitQuaternion<f64> {
        let q0 = euler_quat(self.r0, order, cols);
        if self.f == 0.0 {
            return q0;
        }
        slerp_shortest(&q0, &euler_quat(self.r1, order, cols), self.f)
    }
    fn root_position(&self, plan: &Plan) -> Vector3<f64> {
        Vector3::from_fn(|k, _| plan.root_pos[k].map_or(0.0, |c| self.value(c)))
    }
}

/// The root alignment of take b: `p' = ΔR (p − pivot) + target`, `R' = ΔR · R`.
struct RootAlign {
    rot: Matrix3<f64>,
    quat: UnitQuaternion<f64>,
    pivot: Vector3<f64>,
    target: Vector3<f64>,
}

/// Heading (rad) of a root rotation about `up`: the yaw of the rotated horizontal axis
/// `e_i`, `i = up + 1 (mod 3)`, measured toward `e_j`, `j = up + 2 (mod 3)` (so that a rotation
/// by ψ about `up` adds ψ). Falls back to the other horizontal axis when `e_i` points up.
fn heading(r: &Matrix3<f64>, up: usize) -> f64 {
    let (i, j) = ((up + 1) % 3, (up + 2) % 3);
    let f = r.column(i);
    if f[i].hypot(f[j]) > 1e-6 {
        f[j].atan2(f[i])
    } else {
        // e_j maps to the direction at +90° of e_i's heading
        let g = r.column(j);
        g[j].atan2(g[i]) - std::f64::consts::FRAC_PI_2
    }
}

fn root_alignment(
    a: &Bvh,
    b: &Bvh,
    plan: &Plan,
    window: WarpWindow,
    time_map: TimeMap,
    opts: &BlendOptions,
) -> Result<RootAlign, Error> {
    let up = opts.up_axis;
    let sa = Sample::at(a, window.t0);
    let sb = Sample::at(b, time_map.apply(window.t0));
    let mut rot = Matrix3::identity();
    if opts.align.heading {
        let RotPlan::Euler { order, cols } = &plan.rot[0] else {
            return Err(Error::Invalid(format!(
                "heading alignment needs three rotation channels on the root `{}`; use \
                 `--align root` or `--align none`",
                a.joints[0].name
            )));
        };
        let ra = sa.quat(*order, cols).to_rotation_matrix().into_inner();
        let rb = sb.quat(*order, cols).to_rotation_matrix().into_inner();
        rot = axis_rotation(up, heading(&ra, up) - heading(&rb, up));
    }
    let has_pos = plan.root_pos.iter().any(Option::is_some);
    let rotates = rot != Matrix3::identity();
    if has_pos && rotates && plan.root_pos.iter().any(Option::is_none) {
        return Err(Error::Invalid(format!(
            "heading alignment turns the root position, but the root `{}` lacks some of the \
             Xposition Yposition Zposition channels; use `--align root` or `--align none`",
            a.joints[0].name
        )));
    }
    let pivot = sb.root_position(plan);
    let mut target = pivot;
    if opts.align.root {
        let pa = sa.root_position(plan);
        for k in (0..3).filter(|&k| k != up) {
            target[k] = pa[k];
        }
    }
    Ok(RootAlign {
        rot,
        quat: UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rot)),
        pivot,
        target,
    })
}

/// Blends take `a` into take `b` through `window` (see the module doc). `time_map` re-times b;
/// the output has a's skeleton, frame time and clock, and ends when b ends.
pub fn blend(
    a: &Bvh,
    b: &Bvh,
    window: WarpWindow,
    time_map: TimeMap,
    opts: &BlendOptions,
) -> Result<Bvh, Error> {
    check_same_skeleton(a, b)?;
    if opts.up_axis > 2 {
        return Err(Error::Invalid(format!(
            "up axis {} is not 0 (X), 1 (Y) or 2 (Z)",
            opts.up_axis
        )));
    }
    if a.frames == 0 || b.frames == 0 {
        return Err(Error::Invalid("cannot blend a take without frames".into()));
    }
    if !(time_map.scale > 0.0 && time_map.scale.is_finite() && time_map.offset.is_finite()) {
        return Err(Error::Invalid(format!(
            "time map of take b: the scale must be positive, not {}",
            time_map.scale
        )));
    }
    if !(window.t0 >= 0.0 && window.t0 < window.t1) {
        return Err(Error::Invalid(format!(
            "window {window}: the start must be ≥ 0 and before the end"
        )));
    }
    // the window must lie inside both takes (b on its own clock)
    let eps = 1e-9;
    let end_a = (a.frames - 1) as f64 * a.frame_time;
    let end_b = (b.frames - 1) as f64 * b.frame_time;
    if window.t1 > end_a + eps {
        return Err(Error::Invalid(format!(
            "window {window} ends after take a, which lasts {end_a} s; end the window by then"
        )));
    }
    let (b0, b1) = (time_map.apply(window.t0), time_map.apply(window.t1));
    if b0 < -eps || b1 > end_b + eps {
        return Err(Error::Invalid(format!(
            "window {window} maps to {b0}..{b1} s of take b, which lasts {end_b} s; move the \
             window or change the time offset of take b"
        )));
    }

    let plan = Plan::new(a);
    let align = root_alignment(a, b, &plan, window, time_map, opts)?;
    let dt = a.frame_time;
    let end = (end_b - time_map.offset) / time_map.scale;
    let frames = ((end / dt + eps).floor() as usize + 1).max((window.t1 / dt).ceil() as usize + 1);
    let nc = a.channel_count;
    let mut motion = Vec::with_capacity(frames * nc);

    for k in 0..frames {
        let t = k as f64 * dt;
        // before the window: take a as it is
        if t < window.t0 - eps {
            motion.extend_from_slice(a.frame(k));
            continue;
        }
        let lambda = opts.ramp.value((t - window.t0) / (window.t1 - window.t0));
        let ra = (lambda < 1.0).then(|| a.frame(k.min(a.frames - 1)));
        let sb = Sample::at(b, time_map.apply(t));
        let start = motion.len();
        motion.extend(std::iter::repeat_n(0.0, nc));
        let (done, row) = motion.split_at_mut(start);
        let prev = (k > 0).then(|| &done[start - nc..]);

        // positions: linear, b's root aligned
        let root_b = align.rot * (sb.root_position(&plan) - align.pivot) + align.target;
        for &c in &plan.pos {
            let vb = match plan.root_pos.iter().position(|&rc| rc == Some(c)) {
                Some(axis) => root_b[axis],
                None => sb.value(c),
            };
            row[c] = match ra {
                Some(ra) => (1.0 - lambda) * ra[c] + lambda * vb,
                None => vb,
            };
        }
        // rotations: slerp on the shortest arc, back to the channels nearest the last frame
        for (j, rp) in plan.rot.iter().enumerate() {
            match rp {
                RotPlan::None => {}
                RotPlan::Euler { order, cols } => {
                    let mut qb = sb.quat(*order, cols);
                    if j == 0 {
                        qb = align.quat * qb;
                    }
                    let q = match ra {
                        Some(ra) => slerp_shortest(&euler_quat(ra, *order, cols), &qb, lambda),
                        None => qb,
                    };
                    let reference = prev.or(ra).unwrap_or(sb.r0);
                    let near = [
                        rad(reference[cols[0]]),
                        rad(reference[cols[1]]),
                        rad(reference[cols[2]]),
                    ];
                    let m = q.to_rotation_matrix().into_inner();
                    let angles = matrix_to_euler_near(*order, &m, near);
                    for (c, v) in cols.iter().zip(angles) {
                        row[*c] = v.to_degrees();
                    }
                }
                RotPlan::Angles { cols } => {
                    for &c in cols {
                        let vb = sb.angle(c);
                        let v = match ra {
                            Some(ra) => {
                                (1.0 - lambda) * ra[c] + lambda * nearest_turn_deg(vb, ra[c])
                            }
                            None => vb,
                        };
                        row[c] = match prev {
                            Some(p) => nearest_turn_deg(v, p[c]),
                            None => v,
                        };
                    }
                }
            }
        }
    }
    // every value at the precision the first take was read with
    let decimals = a
        .precision()
        .map_or_else(Vec::new, |d| vec![d; motion.len()]);
    Ok(Bvh {
        joints: a.joints.clone(),
        frame_time: dt,
        frames,
        channel_count: nc,
        motion,
        first_frame: 0,
        decimals,
    })
}

/// Chains several takes of one skeleton: `takes[0]` until `windows[0]`, then `takes[1]` until
/// `windows[1]`, … ("warp windows"). Windows are on the output clock (the first take's) and
/// must follow one another; `time_maps[i]` re-times `takes[i + 1]` (empty: no re-timing).
pub fn blend_chain(
    takes: &[&Bvh],
    windows: &[WarpWindow],
    time_maps: &[TimeMap],
    opts: &BlendOptions,
) -> Result<Bvh, Error> {
    let Some((first, rest)) = takes.split_first() else {
        return Err(Error::Invalid("blending needs at least one take".into()));
    };
    if windows.len() != rest.len() {
        return Err(Error::Invalid(format!(
            "{} takes need {} windows, not {}",
            takes.len(),
            rest.len(),
            windows.len()
        )));
    }
    if !time_maps.is_empty() && time_maps.len() != rest.len() {
        return Err(Error::Invalid(format!(
            "{} takes need {} time maps (one per take after the first) or none, not {}",
            takes.len(),
            rest.len(),
            time_maps.len()
        )));
    }
    for w in windows.windows(2) {
        if w[1].t0 < w[0].t1 {
            return Err(Error::Invalid(format!(
                "window {} starts before window {} ends; windows must follow one another",
                w[1], w[0]
            )));
        }
    }
    let mut out = (*first).clone();
    for (i, (take, window)) in rest.iter().zip(windows).enumerate() {
        let tm = time_maps.get(i).copied().unwrap_or_default();
        out = blend(&out, take, *window, tm, opts)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_window_align_time_map() {
        let w: WarpWindow = "2.0:2.6".parse().unwrap();
        assert_eq!((w.t0, w.t1), (2.0, 2.6));
        assert_eq!(w.to_string().parse::<WarpWindow>().unwrap(), w);
        for bad in ["2.6:2.0", "2.0", "-1:2", "a:b"] {
            let e = bad.parse::<WarpWindow>().unwrap_err().to_string();
            assert!(e.contains("expected `T0:T1`"), "{e}");
        }
        assert_eq!("root,heading".parse::<Align>().unwrap(), Align::ALL);
        assert_eq!("none".parse::<Align>().unwrap(), Align::NONE);
        assert_eq!(
            "heading".parse::<Align>().unwrap(),
            Align {
                root: false,
                heading: true
            }
        );
        for a in [Align::NONE, Align::ALL] {
            assert_eq!(a.to_string().parse::<Align>().unwrap(), a);
        }
        assert!("root,feet".parse::<Align>().is_err());
        let tm: TimeMap = "0.35:1.1".parse().unwrap();
        assert_eq!((tm.offset, tm.scale), (0.35, 1.1));
        assert_eq!("0.2".parse::<TimeMap>().unwrap().scale, 1.0);
        assert!("0.2:0".parse::<TimeMap>().is_err());
    }

    #[test]
    fn heading_adds_rotations_about_up() {
        for up in 0..3 {
            let base = euler_to_matrix(EulerOrder::ZXY, [0.3, -0.2, 0.7]);
            let h0 = heading(&base, up);
            let turned = axis_rotation(up, 0.9) * base;
            let d = heading(&turned, up) - h0;
            let d = d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
            assert!((d - 0.9).abs() < 1e-12, "up {up}: {d}");
        }
    }
}
