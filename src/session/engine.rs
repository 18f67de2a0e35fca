//! The computations the workbench asks for, behind one small trait so that the workbench does
//! not care which stage functions compute them ([`Engine`]), and the built-in engine over the
//! library ([`Builtin`]).
//!
//! Every engine call gets a [`Control`]: it reports progress (0‥1) and polls for
//! cancellation, so that the terminal UI can run it on a worker thread.

use crate::dynamics::{Workspace, rnea};
use crate::error::Error;
use crate::io::bvh::{Bvh, Channel};
use crate::model::{JointKind, Model, ModelBuilder};
use crate::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::{Matrix3, Vector3};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

/// Progress and cancellation shared between a computation and whoever waits for it.
#[derive(Debug, Default)]
pub struct Control {
    cancel: AtomicBool,
    /// Progress in parts per million.
    progress: AtomicU32,
}

impl Control {
    /// Asks the computation to stop at its next check.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
    /// True once [`cancel`](Self::cancel) was called.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
    /// Records progress `f` in 0‥1.
    pub fn set_progress(&self, f: f64) {
        self.progress
            .store((f.clamp(0.0, 1.0) * 1e6) as u32, Ordering::Relaxed);
    }
    /// Progress in 0‥1.
    pub fn progress(&self) -> f64 {
        f64::from(self.progress.load(Ordering::Relaxed)) / 1e6
    }
    /// `Err(Cancelled)` once cancelled; engines call it in their loops.
    pub fn check(&self) -> Result<(), Error> {
        if self.is_cancelled() {
            Err(Error::Invalid("cancelled".into()))
        } else {
            Ok(())
        }
    }
}

/// Joint model of a BVH take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointModel {
    /// One revolute joint per rotation channel, one prismatic per position channel (the
    /// paper's).
    Euler,
    /// One spherical joint per BVH joint, a free root.
    Ball,
}

/// Body sex for the anthropometric tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sex {
    Female,
    Male,
}

/// Ground contact model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Contact {
    /// The avatar hangs from its root (top-down inverse dynamics).
    None,
    /// Ground reactions estimated at the feet.
    Feet,
}

/// Smoothing applied to q before differentiation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Smooth {
    None,
    /// The paper's Gaussian kernel, standard deviation in seconds.
    Gaussian {
        width_s: f64,
    },
    /// Zero-lag Butterworth low-pass, cutoff in Hz.
    Butterworth {
        cutoff_hz: f64,
    },
}

impl std::str::FromStr for Smooth {
    type Err = String;
    /// `none`, `gaussian:W` (seconds), `butterworth:F` or `butterworth:Fhz` (Hz).
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("expected none, gaussian:W (s) or butterworth:F (Hz), found '{s}'");
        if s == "none" {
            return Ok(Smooth::None);
        }
        let (kind, x) = s.split_once(':').ok_or_else(bad)?;
        let x = x.trim_end_matches("hz").trim_end_matches("Hz");
        let x: f64 = x.parse().map_err(|_| bad())?;
        if !(x.is_finite() && x > 0.0) {
            return Err(format!("{s}: the parameter must be positive"));
        }
        match kind {
            "gaussian" => Ok(Smooth::Gaussian { width_s: x }),
            "butterworth" => Ok(Smooth::Butterworth { cutoff_hz: x }),
            _ => Err(bad()),
        }
    }
}

impl std::fmt::Display for Smooth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Smooth::None => write!(f, "none"),
            Smooth::Gaussian { width_s } => write!(f, "gaussian:{width_s}"),
            Smooth::Butterworth { cutoff_hz } => write!(f, "butterworth:{cutoff_hz}hz"),
        }
    }
}

/// Everything the computations depend on besides the take. SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    /// Total body mass (kg).
    pub body_mass: f64,
    pub sex: Sex,
    /// Length unit of the take in metres per file unit; `None` = detect from the stature.
    pub unit: Option<f64>,
    pub joints: JointModel,
    pub smooth: Smooth,
    pub contact: Contact,
    /// Computed-torque gains (1/s², 1/s).
    pub kp: f64,
    pub kv: f64,
    /// Integrator name (`euler`, `semi-implicit`, `rk4`, `dopri5`).
    pub integrator: String,
    /// Simulation step (s).
    pub dt: f64,
    /// Per-link mass overrides (kg), by BVH joint name.
    pub link_mass: BTreeMap<String, f64>,
    /// BVH joints whose coordinates are locked at the rest pose.
    pub lock: Vec<String>,
    /// Default blend window length (s).
    pub blend_window: f64,
    /// Motor torque constant Km (N·m/A) for `report motor`.
    pub motor_km: f64,
    /// Gear ratio N (motor turns per joint turn) for `report motor`.
    pub motor_gear: f64,
    /// Gearbox efficiency η in (0, 1] for `report motor`.
    pub motor_efficiency: f64,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            body_mass: 75.0,
            sex: Sex::Male,
            unit: None,
            joints: JointModel::Euler,
            smooth: Smooth::Gaussian { width_s: 0.02 },
            contact: Contact::None,
            kp: 400.0,
            kv: 40.0,
            integrator: "rk4".into(),
            dt: 0.001,
            link_mass: BTreeMap::new(),
            lock: vec![],
            blend_window: 0.5,
            motor_km: 0.1,
            motor_gear: 100.0,
            motor_efficiency: 1.0,
        }
    }
}

/// A loaded take: the plain BVH description and a short name.
#[derive(Debug, Clone)]
pub struct Take {
    pub name: String,
    /// Where it came from (a path, or `demo:walk`).
    pub source: String,
    pub bvh: Arc<Bvh>,
}

/// A per-frame table: `frames × names.len()` values, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    pub data: Vec<f64>,
}

impl Table {
    /// An all-zero table.
    pub fn zeros(names: Vec<String>, frames: usize) -> Self {
        let data = vec![0.0; frames * names.len()];
        Self { names, data }
    }
    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.names.len()
    }
    /// Number of rows (frames).
    pub fn rows(&self) -> usize {
        self.data.len().checked_div(self.cols()).unwrap_or(0)
    }
    /// Row `k`.
    pub fn row(&self, k: usize) -> &[f64] {
        &self.data[k * self.cols()..(k + 1) * self.cols()]
    }
    /// Row `k`, mutable.
    pub fn row_mut(&mut self, k: usize) -> &mut [f64] {
        let c = self.cols();
        &mut self.data[k * c..(k + 1) * c]
    }
    /// Index of the column called `name`.
    pub fn col_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
    /// Column `j` as a vector.
    pub fn column(&self, j: usize) -> Vec<f64> {
        (0..self.rows()).map(|k| self.row(k)[j]).collect()
    }
}

/// The results of inverse dynamics over a take.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub model: Arc<Model>,
    /// Time of each frame (s).
    pub time: Vec<f64>,
    /// Configuration per frame (`nq` columns, rad / m).
    pub q: Table,
    /// Velocity (`nv` columns, rad/s, m/s).
    pub v: Table,
    /// Acceleration (`nv` columns, rad/s², m/s²).
    pub a: Table,
    /// Generalized forces (`nv` columns, N·m / N).
    pub tau: Table,
    /// Metres per file unit used for the take.
    pub scale: f64,
}

/// The computations behind the workbench. Implementations must be deterministic.
pub trait Engine: Send + Sync {
    /// Reads a take. `demo:walk` is the generated walk of [`crate::io::generate`].
    fn load(&self, path: &Path) -> Result<Take, Error>;
    /// Model, smoothed q, v, a and inverse-dynamics torques of `take` under `params`.
    fn inverse_dynamics(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, Error>;
    /// A computed-torque simulation tracking `take`; the results in the same shape.
    fn simulate(&self, take: &Take, params: &Params, ctl: &Control) -> Result<Analysis, Error>;
    /// Take `b` blended into take `a` over `window` (s).
    fn blend(&self, a: &Take, b: &Take, window: (f64, f64)) -> Result<Take, Error>;
}

/// The engine over the library's stage functions.
#[derive(Debug, Clone, Copy, Default)]
pub struct Builtin;

/// The built-in demo take (`demo:walk`).
pub const DEMO_WALK: &str = "demo:walk";

impl Engine for Builtin {
    fn load(&self, path: &Path) -> Result<Take, Error> {
        let source = path.to_string_lossy().into_owned();
        let bvh = if source == DEMO_WALK {
            crate::io::generate::walk(&crate::io::generate::WalkParams::default())
        } else {
            crate::io::bvh::read(path)?
        };
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| source.clone())
            .replace("demo:", "");
        Ok(Take {
            name,
            source,
            bvh: Arc::new(bvh),
        })
    }

    fn inverse_dynamics(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, Error> {
        let bvh = &take.bvh;
        let scale = match params.unit {
            Some(s) => s,
            None => detect_scale(bvh)?,
        };
        let (model, map) = euler_model(bvh, params, scale, &take.name)?;
        let frames = bvh.frames;
        let dt = bvh.frame_time;
        let time: Vec<f64> = (0..frames).map(|k| k as f64 * dt).collect();

        // channels → q
        let mut q = Table::zeros(model.q_names.clone(), frames);
        for k in 0..frames {
            let raw = bvh.frame(k);
            let row = q.row_mut(k);
            for &(col, ch, is_rot) in &map {
                row[col] = if is_rot {
                    raw[ch].to_radians()
                } else {
                    raw[ch] * scale
                };
            }
        }
        smooth_columns(&mut q, params.smooth, dt)?;

        // q → v, a by central differences
        let (v, a) = differentiate(&q, dt);

        // inverse dynamics frame by frame
        let mut tau = Table::zeros(model.v_names.clone(), frames);
        let mut ws = Workspace::new(&model);
        for k in 0..frames {
            if k % 64 == 0 {
                ctl.check()?;
                ctl.set_progress(k as f64 / frames as f64);
            }
            let t = rnea(&model, &mut ws, q.row(k), v.row(k), a.row(k), None);
            tau.row_mut(k).copy_from_slice(t.as_slice());
        }
        ctl.set_progress(1.0);
        Ok(Analysis {
            model: Arc::new(model),
            time,
            q,
            v,
            a,
            tau,
            scale,
        })
    }

    fn simulate(&self, _take: &Take, _params: &Params, _ctl: &Control) -> Result<Analysis, Error> {
        Err(Error::Invalid(
            "run sim: direct dynamics (dynamics::simulate) is not on main yet".into(),
        ))
    }

    fn blend(&self, _a: &Take, _b: &Take, _window: (f64, f64)) -> Result<Take, Error> {
        Err(Error::Invalid(
            "blend: motion::blend is not on main yet".into(),
        ))
    }
}

/// Metres per file unit from the rest-pose stature: the unit among m, dm, cm, mm and inches
/// that puts the stature in 1.0–2.3 m.
fn detect_scale(bvh: &Bvh) -> Result<f64, Error> {
    let n = bvh.joints.len();
    let mut pos = vec![Vector3::zeros(); n];
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, j) in bvh.joints.iter().enumerate() {
        pos[i] = j.parent.map_or(Vector3::zeros(), |p| pos[p]) + j.offset;
        for p in std::iter::once(pos[i]).chain(j.end_sites.iter().map(|e| pos[i] + e)) {
            lo = lo.min(p.y);
            hi = hi.max(p.y);
        }
    }
    let stature = hi - lo;
    [1.0, 0.1, 0.01, 0.001, 0.0254]
        .into_iter()
        .find(|s| (1.0..=2.3).contains(&(stature * s)))
        .ok_or_else(|| {
            Error::Invalid(format!(
                "rest-pose stature {stature} (file units) fits no length unit; use set unit"
            ))
        })
}

/// The euler joint model of a BVH skeleton (one revolute joint per rotation channel, one
/// prismatic per position channel, channel order, massless fictitious links between; see
/// ARCHITECTURE.md), link masses distributed over the body mass in proportion to bone length
/// (the bone-volume fallback of issue 2 with a common radius) with `link.<name>.mass`
/// overrides, each link a slender rod from its joint to the mean of its children
/// (I = m L²/12 across the rod). Locked joints get fixed joints.
///
/// Returns the model and, per coordinate, `(q column, channel column, is rotation)`.
#[allow(clippy::type_complexity)]
fn euler_model(
    bvh: &Bvh,
    params: &Params,
    scale: f64,
    name: &str,
) -> Result<(Model, Vec<(usize, usize, bool)>), Error> {
    for l in params.lock.iter().chain(params.link_mass.keys()) {
        if bvh.joint_index(l).is_none() {
            return Err(Error::Invalid(format!("no joint called '{l}' in {name}")));
        }
    }
    if params.joints == JointModel::Ball {
        return Err(Error::Invalid(
            "joints ball: the ball-joint BVH model is not on main yet; use joints euler".into(),
        ));
    }
    if params.contact == Contact::Feet {
        return Err(Error::Invalid(
            "contact feet: ground reactions are not on main yet; use contact none".into(),
        ));
    }

    // bone of each joint: towards the mean of its children (or its end sites), metres
    let n = bvh.joints.len();
    let bone: Vec<Vector3<f64>> = (0..n)
        .map(|i| {
            let ends: Vec<Vector3<f64>> = bvh
                .joints
                .iter()
                .filter(|c| c.parent == Some(i))
                .map(|c| c.offset)
                .chain(bvh.joints[i].end_sites.iter().copied())
                .collect();
            if ends.is_empty() {
                Vector3::zeros()
            } else {
                ends.iter().sum::<Vector3<f64>>() / ends.len() as f64 * scale
            }
        })
        .collect();

    // masses: overrides first, the rest shared by bone length
    let fixed: f64 = params.link_mass.values().sum();
    if fixed > params.body_mass {
        return Err(Error::Invalid(format!(
            "link mass overrides ({fixed} kg) exceed the body mass ({} kg)",
            params.body_mass
        )));
    }
    let free_len: f64 = (0..n)
        .filter(|&i| !params.link_mass.contains_key(&bvh.joints[i].name))
        .map(|i| bone[i].norm())
        .sum();
    let mass: Vec<f64> = (0..n)
        .map(|i| match params.link_mass.get(&bvh.joints[i].name) {
            Some(&m) => m,
            None if free_len > 0.0 => (params.body_mass - fixed) * bone[i].norm() / free_len,
            None => 0.0,
        })
        .collect();

    let mut mb = ModelBuilder::new(name, Vector3::new(0.0, -9.81, 0.0));
    let mut last_body = vec![0usize; n];
    let mut map = vec![];
    for (i, j) in bvh.joints.iter().enumerate() {
        let locked = params.lock.contains(&j.name);
        let mut parent = j.parent.map_or(0, |p| last_body[p]);
        let mut placement = SpatialTransform::from_translation(j.offset * scale);
        let chans: Vec<Channel> = if j.channels.is_empty() || locked {
            vec![]
        } else {
            j.channels.clone()
        };
        let links = chans.len().max(1);
        for c in 0..links {
            let (joint, cname) = match chans.get(c) {
                Some(ch) => {
                    let axis = Vector3::ith(ch.axis(), 1.0);
                    let kind = if ch.is_rotation() {
                        JointKind::Revolute { axis }
                    } else {
                        JointKind::Prismatic { axis }
                    };
                    (kind, format!("{}.{}", j.name, ch.name()))
                }
                None => (JointKind::Fixed, j.name.clone()),
            };
            let inertia = if c + 1 == links {
                rod(mass[i], bone[i])
            } else {
                SpatialInertia::ZERO
            };
            let b = mb.add_body(parent, cname.clone(), cname, joint, placement, inertia);
            if let Some(ch) = chans.get(c) {
                map.push((mb.model().idx_q[b], j.first_channel + c, ch.is_rotation()));
            }
            parent = b;
            placement = SpatialTransform::IDENTITY;
        }
        last_body[i] = parent;
    }
    Ok((mb.build(), map))
}

/// A slender rod of mass `m` from the origin to `bone` (m): COM at the middle,
/// `I = m L²/12 (1 − d dᵀ)` about the COM (plus 1 % along the axis so it is never singular).
fn rod(m: f64, bone: Vector3<f64>) -> SpatialInertia {
    let l2 = bone.norm_squared();
    let inertia = if l2 > 0.0 {
        let d = bone / l2.sqrt();
        (Matrix3::identity() - d * d.transpose() * 0.99) * (m * l2 / 12.0)
    } else {
        Matrix3::identity() * (m * 1e-4)
    };
    SpatialInertia::new(m, bone * 0.5, inertia)
}

/// Smooths every column of `q` in place. The Gaussian kernel (the paper's, standard deviation
/// `width_s`, truncated at 3σ) is renormalised over the samples inside the take at the ends,
/// so the ends do not droop toward zero.
fn smooth_columns(q: &mut Table, smooth: Smooth, dt: f64) -> Result<(), Error> {
    match smooth {
        Smooth::None => Ok(()),
        Smooth::Butterworth { .. } => Err(Error::Invalid(
            "smooth butterworth: the Butterworth filter is not on main yet; use gaussian:W".into(),
        )),
        Smooth::Gaussian { width_s } => {
            let sigma = width_s / dt;
            let half = (3.0 * sigma).ceil() as isize;
            let w: Vec<f64> = (-half..=half)
                .map(|k| (-0.5 * (k as f64 / sigma).powi(2)).exp())
                .collect();
            let rows = q.rows() as isize;
            for j in 0..q.cols() {
                let x = q.column(j);
                for k in 0..rows {
                    let (mut s, mut ws) = (0.0, 0.0);
                    for (o, wk) in (-half..=half).zip(&w) {
                        let i = k + o;
                        if (0..rows).contains(&i) {
                            s += wk * x[i as usize];
                            ws += wk;
                        }
                    }
                    q.row_mut(k as usize)[j] = s / ws;
                }
            }
            Ok(())
        }
    }
}

/// Central differences: `v_k = (q_{k+1} − q_{k−1}) / 2dt`, `a_k = (q_{k+1} − 2q_k + q_{k−1}) /
/// dt²`, one-sided at the ends (the euler model's coordinates are all scalar, so plain
/// differences are the manifold differences).
fn differentiate(q: &Table, dt: f64) -> (Table, Table) {
    let (rows, cols) = (q.rows(), q.cols());
    let mut v = Table::zeros(q.names.clone(), rows);
    let mut a = Table::zeros(q.names.clone(), rows);
    if rows < 3 {
        return (v, a);
    }
    for k in 0..rows {
        let (km, kp) = (k.saturating_sub(1), (k + 1).min(rows - 1));
        let kc = k.clamp(1, rows - 2);
        for j in 0..cols {
            v.row_mut(k)[j] = (q.row(kp)[j] - q.row(km)[j]) / ((kp - km) as f64 * dt);
            a.row_mut(k)[j] =
                (q.row(kc + 1)[j] - 2.0 * q.row(kc)[j] + q.row(kc - 1)[j]) / (dt * dt);
        }
    }
    (v, a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_walk_has_the_paper_euler_model_and_body_mass() {
        let take = Builtin.load(Path::new(DEMO_WALK)).unwrap();
        let params = Params::default();
        let r = Builtin
            .inverse_dynamics(&take, &params, &Control::default())
            .unwrap();
        // 21 joints × 3 rotations + 3 root translations
        assert_eq!(r.model.nv, 66);
        assert!((r.model.total_mass() - 75.0).abs() < 1e-9);
        assert_eq!(r.scale, 0.01);
        assert!(r.tau.data.iter().all(|x| x.is_finite()));
    }

    #[test]
    fn gaussian_smoothing_keeps_a_constant_and_a_line() {
        let mut q = Table::zeros(vec!["a".into(), "b".into()], 50);
        for k in 0..50 {
            q.row_mut(k).copy_from_slice(&[2.0, 0.1 * k as f64]);
        }
        smooth_columns(&mut q, Smooth::Gaussian { width_s: 0.05 }, 0.01).unwrap();
        for k in 0..50 {
            assert!((q.row(k)[0] - 2.0).abs() < 1e-12);
            // interior samples of a line are unchanged by a symmetric kernel
            if (15..35).contains(&k) {
                assert!((q.row(k)[1] - 0.1 * k as f64).abs() < 1e-9);
            }
        }
    }
}
