//! What smoothing does to real takes: the smoothness / fidelity trade the user tunes with
//! `--smooth`.
//!
//! For every take in a folder (default `../shared/data/bvh`) and every smoothing method, over
//! all rotation coordinates of the euler model (BVH rotation channels in rad, made continuous
//! with `make_euler_continuous` first):
//! - `rms q̈`: RMS of the second difference `(q[k+1] − 2q[k] + q[k−1])/dt²` (rad/s²), raw and
//!   smoothed, and their ratio;
//! - `rms dev` / `max dev`: deviation of the smoothed angles from the capture (degrees).
//!
//! Run: `cargo run --example smoothing_tradeoff [FOLDER]`

use articula::io::bvh::{Bvh, read};
use articula::motion::smooth::{SmoothSpec, Smoother};
use articula::motion::unwrap::{AngleUnit, make_euler_continuous, unwrap_angles};
use articula::rotation::EulerOrder;
use std::path::PathBuf;

/// The rotation channels of `take` as continuous columns (rad), one per channel.
fn rotation_columns(take: &Bvh) -> Vec<Vec<f64>> {
    let mut cols = vec![];
    for j in &take.joints {
        let rc: Vec<(usize, usize)> = j
            .channels
            .iter()
            .enumerate()
            .filter(|(_, c)| c.is_rotation())
            .map(|(i, c)| (j.first_channel + i, c.axis()))
            .collect();
        let raw = |col: usize| -> Vec<f64> {
            (0..take.frames)
                .map(|k| take.frame(k)[col].to_radians())
                .collect()
        };
        let order = (rc.len() == 3)
            .then(|| EulerOrder::from_axes([rc[0].1, rc[1].1, rc[2].1]))
            .flatten();
        match order {
            Some(order) => {
                let mut frames: Vec<[f64; 3]> = (0..take.frames)
                    .map(|k| {
                        let f = take.frame(k);
                        [rc[0].0, rc[1].0, rc[2].0].map(|c| f[c].to_radians())
                    })
                    .collect();
                make_euler_continuous(order, &mut frames);
                for i in 0..3 {
                    cols.push(frames.iter().map(|f| f[i]).collect());
                }
            }
            None => {
                for (c, _) in rc {
                    let mut x = raw(c);
                    unwrap_angles(AngleUnit::Radians, &mut x);
                    cols.push(x);
                }
            }
        }
    }
    cols
}

fn rms_accel(cols: &[Vec<f64>], dt: f64) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for c in cols {
        for w in c.windows(3) {
            let a = (w[2] - 2.0 * w[1] + w[0]) / (dt * dt);
            sum += a * a;
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt()
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
        "| take | fps | smoothing | −3 dB (Hz) | rms q̈ raw (rad/s²) | rms q̈ smoothed | ratio | rms dev (°) | max dev (°) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for path in &takes {
        let take = read(path)?;
        if take.frames < 20 {
            continue;
        }
        let dt = take.frame_time;
        let raw = rotation_columns(&take);
        let raw_acc = rms_accel(&raw, dt);
        if raw_acc == 0.0 {
            continue; // a static take: nothing to smooth
        }
        let name = path.file_name().unwrap().to_string_lossy();
        for spec in &specs {
            let mut s = Smoother::new(*spec, dt)?;
            let mut cols = raw.clone();
            for c in &mut cols {
                s.smooth(c);
            }
            let acc = rms_accel(&cols, dt);
            let (mut sq, mut n, mut worst) = (0.0, 0usize, 0.0f64);
            for (c, r) in cols.iter().zip(&raw) {
                for (x, y) in c.iter().zip(r) {
                    let d = (x - y).to_degrees();
                    sq += d * d;
                    n += 1;
                    worst = worst.max(d.abs());
                }
            }
            println!(
                "| {name} | {:.0} | {spec} | {:.1} | {raw_acc:.1} | {acc:.1} | {:.3} | {:.3} | {:.2} |",
                1.0 / dt,
                spec.minus3db_hz().unwrap_or(f64::INFINITY),
                acc / raw_acc,
                (sq / n as f64).sqrt(),
                worst
            );
        }
    }
    Ok(())
}
