//! What smoothing does to the inverse dynamics of real takes: peak knee torque and torque jerk
//! before and after, for each `--smooth` method (the smoothness / fidelity trade).
//!
//! For every walking, running, kicking or dancing take in a folder (default `../shared/data/bvh`):
//! the BVH rotation channels are made continuous (`make_euler_continuous`), the take becomes the
//! euler model (detected up axis and unit, automatic position modes, 75 kg de Leva body) and its
//! q; each q column is smoothed, q̇ and q̈ come from second-order differences, and `rnea` gives
//! τ (top-down: no ground reaction, the root carries the residual). Reported over the joint
//! coordinates (root excluded; N·m/s, or N/s on the prismatic coordinates of takes with
//! position channels on every joint): the RMS of the torque jerk `dτ/dt`, and the peak |τ|
//! over the left knee's rotation coordinates (N·m). Frame 0 is dropped (a rest pose in the
//! CMU-derived takes).
//!
//! Run: `cargo run --example smoothing_torques [FOLDER]`

use articula::dynamics::{Workspace, rnea};
use articula::io::bvh::{PositionMode, detect_unit, detect_up, read, resolve_position_modes};
use articula::model::bvh::{BvhModelOptions, build_bvh_model};
use articula::motion::derive::{differentiate, second_derivative};
use articula::motion::smooth::{SmoothSpec, Smoother};
use articula::motion::take::Trajectory;
use articula::motion::unwrap::make_euler_continuous;
use articula::rotation::EulerOrder;
use std::path::PathBuf;

const LEFT_KNEES: [&str; 4] = ["LeftLeg", "lShin", "LowerLeg_L", "LeftLowLeg"];

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
        "none",
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
    println!("| take | smoothing | rms dτ/dt (N·m/s) | peak left-knee |τ| (N·m) |");
    println!("|---|---|---|---|");
    for path in &takes {
        let mut take = read(path)?;
        if take.frames < 20 {
            continue;
        }
        take.motion.drain(..take.channel_count);
        take.frames -= 1;
        // continuous Euler channels, written back in degrees
        for j in take.joints.clone() {
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
            let cols = [rc[0].0, rc[1].0, rc[2].0];
            let mut frames: Vec<[f64; 3]> = (0..take.frames)
                .map(|k| cols.map(|c| take.frame(k)[c].to_radians()))
                .collect();
            make_euler_continuous(order, &mut frames);
            for (k, f) in frames.iter().enumerate() {
                for (c, v) in cols.iter().zip(f) {
                    take.motion[k * take.channel_count + c] = v.to_degrees();
                }
            }
        }
        let up = detect_up(&take);
        let (unit, stature) = detect_unit(&take, up);
        let positions = resolve_position_modes(&take, PositionMode::Auto);
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let opts = BvhModelOptions::new(name.clone(), unit.scale_to_m(), up, positions);
        let Ok((model, map)) = build_bvh_model(&take, &opts) else {
            continue;
        };
        let Some(knee) = LEFT_KNEES
            .iter()
            .find_map(|k| take.joint_index(k))
            .map(|j| take.joints[j].name.clone())
        else {
            continue;
        };
        let knee_v: Vec<usize> = (0..model.nv)
            .filter(|&i| {
                let n = &model.v_names[i];
                n.starts_with(&format!("{knee}.")) && n.ends_with("rotation")
            })
            .collect();
        // the root's coordinates: those of the first BVH joint
        let root = format!("{}.", take.joints[0].name);
        let joint_v: Vec<usize> = (0..model.nv)
            .filter(|&i| !model.v_names[i].starts_with(&root))
            .collect();
        let raw = Trajectory::from_bvh(&take, &model, &map).q;
        let (n, dt) = (raw.len(), take.frame_time);
        let mut ws = Workspace::new(&model);
        for spec in &specs {
            let mut s = Smoother::new(*spec, dt)?;
            let (mut q, mut v, mut a) = (raw.clone(), raw.clone(), raw.clone());
            let (mut col, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            for i in 0..model.nq {
                col.iter_mut().zip(&raw).for_each(|(c, r)| *c = r[i]);
                s.smooth(&mut col);
                differentiate(&col, dt, &mut d1);
                second_derivative(&col, dt, &mut d2);
                for k in 0..n {
                    q[k][i] = col[k];
                    v[k][i] = d1[k];
                    a[k][i] = d2[k];
                }
            }
            let tau: Vec<Vec<f64>> = (0..n)
                .map(|k| {
                    rnea(&model, &mut ws, &q[k], &v[k], &a[k], None)
                        .as_slice()
                        .to_vec()
                })
                .collect();
            let (mut sum, mut count) = (0.0, 0usize);
            let mut jerk = vec![0.0; n];
            for &i in &joint_v {
                col.iter_mut().zip(&tau).for_each(|(c, t)| *c = t[i]);
                differentiate(&col, dt, &mut jerk);
                sum += jerk.iter().map(|x| x * x).sum::<f64>();
                count += n;
            }
            let peak = tau
                .iter()
                .flat_map(|t| knee_v.iter().map(move |&i| t[i].abs()))
                .fold(0.0, f64::max);
            println!(
                "| {name} ({:.2} m, {:.0} fps) | {spec} | {:.0} | {peak:.1} |",
                stature,
                1.0 / dt,
                (sum / count as f64).sqrt()
            );
        }
    }
    Ok(())
}
