//! The computations the workbench asks for, behind one small trait so that the workbench does
//! not care which stage functions compute them ([`Engine`]), and the built-in engine over the
//! library ([`Builtin`]).
//!
//! Every engine call gets a [`Control`]: it reports progress (0‥1) and polls for
//! cancellation, so that the terminal UI can run it on a worker thread.

use crate::error::Error;
use crate::io::bvh::{Bvh, LengthUnit, detect_up};
use crate::model::Model;
use crate::model::anthropometry::BodyParams;
use crate::motion::blend::{Align, BlendOptions, TimeMap, WarpWindow};
use crate::motion::smooth::SmoothSpec;
use crate::pipeline::{self, TakeOptions};
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

// the joint model, sex and contact model are the pipeline's own types
pub use crate::model::anthropometry::Sex;
pub use crate::model::bvh::JointModel;
pub use crate::pipeline::Contact;

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
            smooth: Smooth::Butterworth { cutoff_hz: 6.0 },
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
    /// A one-line summary for messages (a simulation's tracking error), or empty.
    pub note: String,
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
            // as `pipeline::load_take`: a rest pose stored as frame 0 is dropped
            let mut bvh = crate::io::bvh::read(path)?;
            crate::motion::trim::trim_rest_first_frame(&mut bvh);
            bvh
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
        // the pipeline's stages: axes and unit, model, q, unwrap, smooth, differentiate
        let opts = take_options(params)?;
        ctl.check()?;
        let t = pipeline::take_from_bvh(Path::new(&take.source), (*take.bvh).clone(), &opts)?;
        ctl.set_progress(0.5);
        ctl.check()?;

        // inverse dynamics, with the estimated ground reactions under `contact feet`
        let mut torques = pipeline::inverse_dynamics(&t.model, &t.states);
        if let Some(g) = pipeline::ground_reactions(&t)? {
            torques.tau = g.tau;
        }
        ctl.set_progress(1.0);
        let table = |names: &[String], rows: &[Vec<f64>]| Table {
            names: names.to_vec(),
            data: rows.concat(),
        };
        let s = &t.states;
        Ok(Analysis {
            q: table(&t.model.q_names, &s.q),
            v: table(&t.model.v_names, &s.v),
            a: table(&t.model.v_names, &s.a),
            tau: table(&t.model.v_names, &torques.tau),
            time: s.time.clone(),
            scale: t.scale_to_m,
            note: String::new(),
            model: Arc::new(t.model),
        })
    }

    fn simulate(&self, take: &Take, params: &Params, ctl: &Control) -> Result<Analysis, Error> {
        // computed-torque tracking of the take's (smoothed) motion (pipeline::simulate)
        let opts = take_options(params)?;
        let t = pipeline::take_from_bvh(Path::new(&take.source), (*take.bvh).clone(), &opts)?;
        ctl.check()?;
        let settings = pipeline::SimSettings::parse(
            &params.integrator,
            params.dt,
            params.kp,
            params.kv,
            0.0,
            None,
        )?;
        let summary = pipeline::simulate(&t, &settings, None)?;
        ctl.set_progress(1.0);
        let r = summary.result;
        let table = |names: &[String], rows: &[Vec<f64>]| Table {
            names: names.to_vec(),
            data: rows.concat(),
        };
        // accelerations are not recorded: differentiate the simulated velocities
        let dt = r.time.get(1).map_or(params.dt, |t1| t1 - r.time[0]);
        let mut a = Table::zeros(t.model.v_names.clone(), r.time.len());
        let mut da = vec![0.0; r.time.len()];
        for j in 0..t.model.nv {
            let vj: Vec<f64> = r.v.iter().map(|row| row[j]).collect();
            crate::motion::derive::differentiate(&vj, dt, &mut da);
            for (k, x) in da.iter().enumerate() {
                a.row_mut(k)[j] = *x;
            }
        }
        Ok(Analysis {
            q: table(&t.model.q_names, &r.q),
            v: table(&t.model.v_names, &r.v),
            a,
            tau: table(&t.model.v_names, &r.tau),
            time: r.time.clone(),
            scale: t.scale_to_m,
            note: format!(
                "tracking error RMS {:.3e} rad, max {:.3e} rad",
                r.rms_error_rad(),
                r.max_error_rad()
            ),
            model: Arc::new(t.model),
        })
    }

    fn blend(&self, a: &Take, b: &Take, window: (f64, f64)) -> Result<Take, Error> {
        // motion::blend: C² ramp, shortest-arc slerp per joint, b's root and heading aligned
        // to a's at the window start
        let opts = BlendOptions {
            align: Align::ALL,
            up_axis: detect_up(&a.bvh).index(),
            ..BlendOptions::default()
        };
        let w = WarpWindow {
            t0: window.0,
            t1: window.1,
        };
        let bvh = crate::motion::blend::blend(&a.bvh, &b.bvh, w, TimeMap::IDENTITY, &opts)?;
        Ok(Take {
            name: format!("{}+{}", a.name, b.name),
            source: format!("blend {} {} {}:{}", a.name, b.name, window.0, window.1),
            bvh: Arc::new(bvh),
        })
    }
}

/// The pipeline's options from the workbench parameters.
fn take_options(params: &Params) -> Result<TakeOptions, Error> {
    Ok(TakeOptions {
        unit: params.unit.map(LengthUnit::Custom),
        joints: params.joints,
        body: BodyParams {
            mass_kg: params.body_mass,
            sex: params.sex,
            link_mass: params.link_mass.clone(),
        },
        smooth: params.smooth.to_string().parse::<SmoothSpec>()?,
        lock: params.lock.clone(),
        contact: params.contact,
        ..TakeOptions::default()
    })
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
    fn smoothing_width_changes_the_torques_and_none_keeps_the_raw_angles() {
        let take = Builtin.load(Path::new(DEMO_WALK)).unwrap();
        let ctl = Control::default();
        let raw = Params {
            smooth: Smooth::None,
            ..Params::default()
        };
        let r0 = Builtin.inverse_dynamics(&take, &raw, &ctl).unwrap();
        // unsmoothed: q is the channel value in radians
        let j = r0.q.col_index("LeftLeg.Xrotation").unwrap();
        let c = take.bvh.joints[take.bvh.joint_index("LeftLeg").unwrap()].first_channel + 1;
        for k in [0, 100, 479] {
            assert!((r0.q.row(k)[j] - take.bvh.frame(k)[c].to_radians()).abs() < 1e-12);
        }
        let wide = Params {
            smooth: Smooth::Gaussian { width_s: 0.05 },
            ..Params::default()
        };
        let r1 = Builtin.inverse_dynamics(&take, &wide, &ctl).unwrap();
        assert_ne!(r0.tau, r1.tau);
    }
}
