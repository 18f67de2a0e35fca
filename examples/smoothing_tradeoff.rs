//! What smoothing does to real takes: the smoothness / fidelity trade the user tunes with
//! `--smooth`.
//!
//! For every take in a folder (default `../shared/data/bvh`) and every smoothing method, over
//! every joint with three rotation channels, smoothed two ways:
//! - **euler** (the paper's joint model): the three channels as angles (rad), made continuous
//!   with `make_euler_continuous`, each smoothed as a column; `rms q̈` is the RMS of the
//!   second difference `(q[k+1] − 2q[k] + q[k−1])/dt²` over all these coordinates (rad/s²);
//! - **ball**: the joint rotation as a quaternion, smoothed with `smooth_quaternions`;
//!   `rms ω̇` is the RMS over components of the body angular acceleration, differentiated twice
//!   on the manifold (`differentiate_quaternions`, then `differentiate_vectors`) (rad/s²);
//! - `dev`: the geodesic angle between the smoothed joint rotation and the captured one, RMS
//!   and max over joints and frames (degrees): what the smoothing changed in the pose.
//!
//! Run: `cargo run --example smoothing_tradeoff [FOLDER] [FIRST_FRAME]`. `FIRST_FRAME` (default
//! 0) drops the frames before it: the CMU-derived takes (`cmu_*`, `pirouette`) start with a
//! rest pose in frame 0, one frame away from the capture, which any smoothing smears over the
//! first frames (50–100° deviations at frame 1).

use articula::io::bvh::{Bvh, read};
use articula::motion::derive::{differentiate_quaternions, differentiate_vectors};
use articula::motion::smooth::{SmoothSpec, Smoother};
use articula::motion::unwrap::make_euler_continuous;
use articula::rotation::{EulerOrder, euler_to_matrix};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use std::path::PathBuf;

/// Per joint with three rotation channels: its name, order and continuous angles (rad) per
/// frame.
fn euler_joints(take: &Bvh) -> Vec<(String, EulerOrder, Vec<[f64; 3]>)> {
    let mut out = vec![];
    for j in &take.joints {
        let rc: Vec<(usize, usize)> = j
            .channels
            .iter()
            .enumerate()
            .filter(|(_, c)| c.is_rotation())
            .map(|(i, c)| (j.first_channel + i, c.axis()))
            .collect();
        if rc.len() != 3 {
            continue;
        }
        let Some(order) = EulerOrder::from_axes([rc[0].1, rc[1].1, rc[2].1]) else {
            continue;
        };
        let mut frames: Vec<[f64; 3]> = (0..take.frames)
            .map(|k| {
                let f = take.frame(k);
                [rc[0].0, rc[1].0, rc[2].0].map(|c| f[c].to_radians())
            })
            .collect();
        make_euler_continuous(order, &mut frames);
        out.push((j.name.clone(), order, frames));
    }
    out
}

fn quat(order: EulerOrder, a: [f64; 3]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(euler_to_matrix(
        order, a,
    )))
}

/// Running sums: Σx², count, max.
#[derive(Default)]
struct Stat(f64, usize, f64);

impl Stat {
    fn add(&mut self, x: f64) {
        self.0 += x * x;
        self.1 += 1;
        self.2 = self.2.max(x.abs());
    }
    fn rms(&self) -> f64 {
        (self.0 / self.1.max(1) as f64).sqrt()
    }
}

/// RMS of the Euler second differences of `frames` (rad/s²).
fn euler_accel(frames: &[[f64; 3]], dt: f64, s: &mut Stat) {
    for w in frames.windows(3) {
        for ((x0, x1), x2) in w[0].iter().zip(&w[1]).zip(&w[2]) {
            s.add((x2 - 2.0 * x1 + x0) / (dt * dt));
        }
    }
}

/// Body angular acceleration components of a quaternion path (rad/s²).
fn ball_accel(q: &[UnitQuaternion<f64>], dt: f64, s: &mut Stat) {
    let mut w = vec![Vector3::zeros(); q.len()];
    let mut a = vec![Vector3::zeros(); q.len()];
    differentiate_quaternions(q, dt, &mut w);
    differentiate_vectors(&w, dt, &mut a);
    for v in &a {
        for i in 0..3 {
            s.add(v[i]);
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "../shared/data/bvh".into()),
    );
    let mut takes: Vec<PathBuf> = std::fs::read_dir(&dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .collect();
    takes.sort();
    let first: usize = std::env::args().nth(2).map_or(Ok(0), |s| s.parse())?;
    let specs: Vec<SmoothSpec> = [
        "gaussian:0.005",
        "gaussian:0.01",
        "gaussian:0.02",
        "gaussian:0.05",
        "butterworth:4hz",
        "butterworth:6hz",
        "butterworth:10hz",
    ]
    .iter()
    .map(|s| s.parse())
    .collect::<Result<_, _>>()?;
    println!(
        "| take | fps | smoothing | −3 dB (Hz) | euler rms q̈ (rad/s²) raw → smoothed | euler dev rms / max (°) | ball rms ω̇ (rad/s²) raw → smoothed | ball dev rms / max (°) | ball max at |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for path in &takes {
        let mut take = read(path)?;
        let drop = first.min(take.frames);
        take.motion.drain(..drop * take.channel_count);
        take.frames -= drop;
        if take.frames < 20 {
            continue;
        }
        let dt = take.frame_time;
        let joints = euler_joints(&take);
        let quats: Vec<Vec<UnitQuaternion<f64>>> = joints
            .iter()
            .map(|(_, o, f)| f.iter().map(|a| quat(*o, *a)).collect())
            .collect();
        let (mut e_raw, mut b_raw) = (Stat::default(), Stat::default());
        for ((_, _, f), q) in joints.iter().zip(&quats) {
            euler_accel(f, dt, &mut e_raw);
            ball_accel(q, dt, &mut b_raw);
        }
        if e_raw.rms() == 0.0 {
            continue; // a static take: nothing to smooth
        }
        let name = path.file_name().unwrap().to_string_lossy();
        for spec in &specs {
            let mut s = Smoother::new(*spec, dt)?;
            let (mut e_acc, mut e_dev, mut b_acc, mut b_dev) = (
                Stat::default(),
                Stat::default(),
                Stat::default(),
                Stat::default(),
            );
            let mut col = vec![0.0; take.frames];
            let mut worst = (0.0, String::new(), 0.0);
            for ((joint, order, frames), q_raw) in joints.iter().zip(&quats) {
                // euler: three columns
                let mut sm = frames.clone();
                for i in 0..3 {
                    col.iter_mut().zip(frames).for_each(|(c, f)| *c = f[i]);
                    s.smooth(&mut col);
                    sm.iter_mut().zip(&col).for_each(|(f, c)| f[i] = *c);
                }
                euler_accel(&sm, dt, &mut e_acc);
                for (a, r) in sm.iter().zip(q_raw) {
                    e_dev.add(quat(*order, *a).angle_to(r).to_degrees());
                }
                // ball: the quaternion path
                let mut q = q_raw.clone();
                s.smooth_quaternions(&mut q);
                ball_accel(&q, dt, &mut b_acc);
                for (k, (a, r)) in q.iter().zip(q_raw).enumerate() {
                    let d = a.angle_to(r).to_degrees();
                    b_dev.add(d);
                    if d > worst.0 {
                        worst = (d, joint.clone(), k as f64 * dt);
                    }
                }
            }
            println!(
                "| {name} | {:.0} | {spec} | {:.1} | {:.1} → {:.1} ({:.2}) | {:.3} / {:.2} | {:.1} → {:.1} ({:.2}) | {:.3} / {:.2} | {} @ {:.2} s |",
                1.0 / dt,
                spec.minus3db_hz().unwrap_or(f64::INFINITY),
                e_raw.rms(),
                e_acc.rms(),
                e_acc.rms() / e_raw.rms(),
                e_dev.rms(),
                e_dev.2,
                b_raw.rms(),
                b_acc.rms(),
                b_acc.rms() / b_raw.rms(),
                b_dev.rms(),
                b_dev.2,
                worst.1,
                worst.2,
            );
        }
    }
    Ok(())
}
