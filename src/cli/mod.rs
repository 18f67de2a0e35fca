//! Command-line flags (clap), validated into library settings, and their dispatch.
//!
//! Two steps, as ripgrep does: clap parses raw flags into the structs below (one `…Args` per
//! command); `run` dispatches them to [`commands`], one function per command, which turn them
//! into `pipeline` options and call the library. Nothing computes here.

mod commands;

use anyhow::{Context, Result, bail};
use articula::pipeline::formats::{self, TableFormat};
use articula::pipeline::{self, ModelSource, TakeOptions};
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// articula: a terminal workbench for the dynamics of articulated avatars.
///
/// With no subcommand, opens the terminal UI on the given takes (or on the bundled demo take
/// `data/demo_walk.bvh`).
#[derive(Debug, Parser)]
#[command(
    name = "articula",
    version,
    about,
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Option<Cmd>,
    /// Takes (BVH), DH tables (.toml) or URDFs to open in the terminal UI.
    pub files: Vec<PathBuf>,
    /// Threads for the frames and coordinates worked on in parallel (unwrapping, smoothing,
    /// derivatives, inverse dynamics). Default: all cores (or RAYON_NUM_THREADS); 1 is the
    /// serial path. Results are the same, bit for bit, whatever the number.
    #[arg(long, global = true, value_name = "N")]
    pub threads: Option<usize>,
}

#[derive(Debug, Subcommand)]
pub enum Cmd {
    /// Describe a take: skeleton, channels, frames, unit, up axis, model size, mass, the
    /// segment-mass table and the stature it used.
    Info(InfoArgs),
    /// Write positions, the euler model as URDF, the states inverse dynamics uses, the ground
    /// reactions, or the joint centres as TRC markers. Tables are CSV, or OpenSim's .sto/.mot
    /// when the output ends so (or --format says so).
    Export(ExportArgs),
    /// Make a take (the bundled demo walk is made this way).
    Generate(GenerateArgs),
    /// Inverse dynamics (RNEA): the torque of every coordinate, frame by frame. CSV, or
    /// OpenSim's .sto (`<coord>_moment` N·m, `<coord>_force` N) when the output ends in .sto
    /// (or --format sto).
    Id(IdArgs),
    /// Anatomical joint angles (deg) and net internal moments (N·m, N·m/kg) of a human take:
    /// pelvis, lumbar, hips, knees, ankles, shoulders, elbows, in the joint coordinate system
    /// (Grood & Suntay 1983; ISB, Wu et al. 2002). Flexion, adduction and internal rotation
    /// positive; extensor (ankle: plantarflexor), abductor and external-rotator moments
    /// positive. Ground contact is auto as everywhere (feet when the take stands on a floor);
    /// the joint model defaults to ball here (no gimbal lock; rotations smoothed as rotations).
    Anatomy(AnatomyArgs),
    /// Direct dynamics (ABA): accelerations `a:<coord>` from states and torques.
    Fd(FdArgs),
    /// The joint-space mass matrix D(q) (CRBA), row-major `M:<i>:<j>`, one row per state.
    MassMatrix(MassMatrixArgs),
    /// Forward simulation tracking the take with computed-torque PD control.
    Simulate(SimulateArgs),
    /// Nanoseconds per call of rnea, crba, aba and one RK4 step; with --stages, the
    /// milliseconds of every stage of `articula id` on a take, from the file to the torques.
    Bench(BenchArgs),
    /// Measure the speed/accuracy trade of integrators, steps and joint models; with
    /// --reduce, of locking joints greedily, the one that changes the outputs least first.
    Tradeoff(TradeoffArgs),
    /// Write a cleaned (smoothed) take.
    Smooth(SmoothArgs),
    /// Blend two takes (or chain several) through transition windows.
    Blend(BlendArgs),
    /// Run a take command over many takes (folders, files, @lists), N at a time, each in a
    /// child process, with a sweep of settings, resume, and a summary table:
    /// `articula batch takes/ -o out/ --jobs 4 --vary mass=60,80 -- id --contact auto`.
    Batch(crate::batch::BatchArgs),
    /// Replay a session file headless.
    Run(RunArgs),
}

// the arguments of `articula info` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct InfoArgs {
    take: PathBuf,
    #[command(flatten)]
    opts: TakeArgs,
    /// Machine-readable summary with the keys joints, frames, frame_time, nq, nv,
    /// scale_to_m, stature_m, up, gravity, mass_kg, unit, smooth, segments,
    /// segments_stature_m, human (the joints the skeleton's shape makes its pelvis, hips,
    /// knees, ankles, trunk and arms, or why it is not a human's), notes.
    #[arg(long)]
    json: bool,
}

// the arguments of `articula export` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct ExportArgs {
    what: ExportWhat,
    take: PathBuf,
    #[command(flatten)]
    opts: TakeArgs,
    /// Table format: csv, sto or mot (states, grf). Default: the output's extension
    /// (.sto, .mot), else csv; `-o -` is csv unless given.
    #[arg(long, value_name = "csv|sto|mot")]
    format: Option<String>,
    /// Length unit of `export trc`, declared in its header: mm (default) or m.
    #[arg(long, value_name = "mm|m")]
    trc_units: Option<String>,
    /// Print what was written as JSON (keys command, takes, written, format, frames,
    /// frame_time_s, settings, notes; docs/formats.md); on standard error with `-o -`.
    #[arg(long)]
    json: bool,
    #[arg(short, long)]
    output: PathBuf,
}

// the arguments of `articula generate` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct GenerateArgs {
    what: GenerateWhat,
    #[arg(short, long, default_value = "data/demo_walk.bvh")]
    output: PathBuf,
    /// Frames per second.
    #[arg(long, default_value_t = 120.0, allow_negative_numbers = true)]
    fps: f64,
    /// Length (s).
    #[arg(long, default_value_t = 4.0, allow_negative_numbers = true)]
    duration: f64,
    /// Skeleton scale relative to a 1.72 m adult.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    scale: f64,
}

// the arguments of `articula id` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct IdArgs {
    #[command(flatten)]
    src: SourceArgs,
    #[command(flatten)]
    opts: TakeArgs,
    #[command(flatten)]
    consistency: ConsistencyArgs,
    /// Table format: csv or sto. Default: the output's extension (.sto, .mot), else csv.
    #[arg(long, value_name = "csv|sto")]
    format: Option<String>,
    /// Measured ground reactions instead of the estimate: an OpenSim external-loads .mot
    /// (`<foot>_ground_force_v[xyz]`, `_p[xyz]`, `<foot>_ground_torque_[xyz]`) or a CSV
    /// with `grf:<foot>:x|y|z`, `cop:…`, `moment:…` (as `export grf` writes); N, m, N·m in
    /// the take's world axes, resampled to the take's frames.
    #[arg(long, value_name = "FILE")]
    grf: Option<PathBuf>,
    /// Time (s) of the take's frame at time 0 on the --grf file's clock: the file's time
    /// of frame k is t_k + offset.
    #[arg(
        long,
        value_name = "S",
        allow_negative_numbers = true,
        requires = "grf"
    )]
    grf_offset: Option<f64>,
    #[arg(short, long)]
    output: PathBuf,
}

// the arguments of `articula anatomy` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct AnatomyArgs {
    take: PathBuf,
    #[command(flatten)]
    opts: TakeArgs,
    #[command(flatten)]
    consistency: ConsistencyArgs,
    /// The frames within the smoothing's reach of the take's ends, whose accelerations
    /// are not trustworthy: exclude (the default) leaves them out of the summary's ranges,
    /// include keeps them. The CSV marks them either way (column `edge`).
    #[arg(long, value_name = "exclude|include")]
    edges: Option<String>,
    /// Also write the clinical gait view: hip, knee and ankle moments (N·m/kg) over the
    /// gait cycle from the foot strikes, mean ± SD, left and right, stance shaded, with
    /// the speed-matched Schwartz 2008 band (`.svg` or `.png`; docs/reports.md).
    #[arg(long, value_name = "PATH")]
    gait: Option<PathBuf>,
    #[arg(short, long)]
    output: PathBuf,
}

// the arguments of `articula fd` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct FdArgs {
    #[command(flatten)]
    src: SourceArgs,
    #[command(flatten)]
    opts: TakeArgs,
    /// Torques CSV (`time`, then one column per coordinate, as `articula id` writes).
    #[arg(long)]
    torques: PathBuf,
    #[arg(short, long)]
    output: PathBuf,
}

// the arguments of `articula massmatrix` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct MassMatrixArgs {
    #[command(flatten)]
    src: SourceArgs,
    #[command(flatten)]
    opts: TakeArgs,
    #[arg(short, long)]
    output: PathBuf,
}

// the arguments of `articula simulate` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct SimulateArgs {
    take: PathBuf,
    #[command(flatten)]
    opts: TakeArgs,
    #[command(flatten)]
    sim: SimArgs,
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Print a JSON summary (rms_error_rad, max_error_rad, steps, integrator, dt).
    #[arg(long)]
    json: bool,
}

// the arguments of `articula bench` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct BenchArgs {
    #[command(flatten)]
    src: SourceArgs,
    #[command(flatten)]
    opts: TakeArgs,
    /// JSON; with --stages the keys frames, nv, threads, stages_ms (median per stage),
    /// stages_min_ms, total_ms (file to torques), total_min_ms, contact, repeat, cycled.
    #[arg(long)]
    json: bool,
    /// Batches of at least 2 ms each; the median is reported.
    #[arg(long, default_value_t = 7, conflicts_with_all = ["stages", "edit"])]
    batches: usize,
    /// Time the stages a take goes through in `articula id` (parse, model, coordinates,
    /// unwrap, smooth, derivatives, job, contact, inverse dynamics): min and median.
    #[arg(long, conflicts_with_all = ["urdf", "dh", "states"])]
    stages: bool,
    /// Time a workbench edit on the take: `set SETTING V` then `run id`, the values in
    /// turn (`body.mass=80,70`), as the terminal UI's "recomputed in N ms" (min and
    /// median, the stages each edit reran, and the time to the preview a mass edit of a
    /// reduced take draws first). The take flags set the workbench's take options
    /// (`--contact feet`); see docs/workbench.md.
    #[arg(
        long,
        value_name = "SETTING=V1,V2",
        conflicts_with_all = ["urdf", "dh", "states", "stages"]
    )]
    edit: Option<String>,
    /// With --edit: a workbench setting applied before the first run, `KEY=VALUE`
    /// (`consistent=off`); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE", requires = "edit")]
    set: Vec<String>,
    /// Timed runs of the stages (after one warm-up run), or timed edits with --edit
    /// [default: 5].
    #[arg(long)]
    repeat: Option<usize>,
    /// Cycle the take to this many minutes of frames before timing: frame 0 once, then
    /// frames 1…last forward and backward in turn; the parse is timed on the cycled text.
    #[arg(
        long,
        value_name = "M",
        requires = "stages",
        allow_negative_numbers = true
    )]
    minutes: Option<f64>,
}

// the arguments of `articula tradeoff` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct TradeoffArgs {
    take: PathBuf,
    #[command(flatten)]
    opts: TakeArgs,
    /// Simulated time (s) from the start of the take.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    duration: f64,
    /// Lock joints one by one, the one whose locking changes the outputs (--of) least
    /// first: each step's nv, RNEA time per frame and error on the outputs (peak and RMS,
    /// N·m and %), searched on a subsample of the frames and verified on all.
    #[arg(long, conflicts_with = "duration")]
    reduce: bool,
    /// The outputs of --reduce (comma-separated): anatomical joints (knee_l, hip_r, …),
    /// BVH joints or coordinates. Default: knee_l,knee_r for a human, else every joint.
    #[arg(long, value_delimiter = ',', requires = "reduce")]
    of: Vec<String>,
    /// With --reduce: the steps as JSON (keys take, outputs, coordinates, contact, frames,
    /// search_frames, search_every, output_peak_nm, output_rms_nm, steps, holds, skipped).
    #[arg(long, requires = "reduce")]
    json: bool,
    #[arg(short, long)]
    output: Option<PathBuf>,
}

// the arguments of `articula smooth` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct SmoothArgs {
    take: PathBuf,
    #[command(flatten)]
    opts: TakeArgs,
    /// How the BVH is written: `portable` (every reader reads it alike: constant position
    /// channels below the root folded into the OFFSETs, the root's OFFSET zero; see
    /// docs/animation-tools.md) or `as-read` (every joint's channels and OFFSET as the
    /// input had them).
    #[arg(long, default_value = "portable")]
    bvh_style: String,
    /// Print what was written as JSON (as `export --json`); on standard error with `-o -`.
    #[arg(long)]
    json: bool,
    #[arg(short, long)]
    output: PathBuf,
}

// the arguments of `articula blend` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct BlendArgs {
    /// Takes in order: the first, then each one blended in at its window.
    #[arg(required = true, num_args = 2..)]
    takes: Vec<PathBuf>,
    /// Transition window `t0:t1` (s, on the first take's clock), one per following take.
    #[arg(long, required = true)]
    window: Vec<String>,
    /// What of take b to align to take a at the window: `root,heading`, `root`, `none`.
    #[arg(long, default_value = "root,heading")]
    align: String,
    /// Time offset (s) of take b.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    offset: f64,
    /// Time scale of take b.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    time_scale: f64,
    /// Up axis of the takes (x, y, z); default: detected from the first take.
    #[arg(long)]
    up: Option<String>,
    /// Keep frame 0 of each take even when it is a rest pose before the motion (dropped by
    /// default, as every other command does).
    #[arg(long)]
    keep_first_frame: bool,
    /// How the BVH is written: `portable` (every reader reads it alike: constant position
    /// channels below the root folded into the OFFSETs, the root's OFFSET zero; see
    /// docs/animation-tools.md) or `as-read` (every joint's channels and OFFSET as the
    /// input had them).
    #[arg(long, default_value = "portable")]
    bvh_style: String,
    /// Print what was written as JSON (as `export --json`); on standard error with `-o -`.
    #[arg(long)]
    json: bool,
    #[arg(short, long)]
    output: PathBuf,
}

// the arguments of `articula run` (its help is the variant's doc)
#[derive(Debug, Args)]
pub struct RunArgs {
    session: PathBuf,
    /// Folder for the session's outputs (relative paths in the session go here).
    #[arg(long, default_value = ".")]
    out: PathBuf,
    /// Print the replay as JSON (keys session, ok, error, commands, expectations — each
    /// `expect` with its line, result and pass — written, messages), also when it fails.
    #[arg(long)]
    json: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExportWhat {
    /// World position of every joint, per frame (m, the take's axes).
    Positions,
    /// The model as URDF.
    Urdf,
    /// The model as MuJoCo MJCF: a free root, ball or hinge joints, ellipsoid links, a floor,
    /// gravity along −up, a motor per joint DoF (gear 1).
    Mjcf,
    /// q, v, a per frame, exactly as inverse dynamics uses them (.sto: degrees for rotations,
    /// `<coord>`, `<coord>_u`, `<coord>_dudt`).
    States,
    /// Ground reactions per foot (force N, centre of pressure m, free moment N·m; world axes);
    /// .mot: OpenSim external loads, with the ExternalLoads XML `NAME.xml` beside it.
    Grf,
    /// Every joint's world position as a marker, OpenSim's .trc (--trc-units mm|m).
    Trc,
    /// glTF 2.0 binary (.glb) for game engines and 3-D tools: the skeleton, the superquadric
    /// links skinned to it and the take's animation (m, Y up: turned from the take's up axis).
    Gltf,
}

/// Every export: its name in `pipeline::formats::export` (and in flag checks and messages).
const EXPORTS: &[(ExportWhat, &str)] = &[
    (ExportWhat::Positions, "positions"),
    (ExportWhat::Urdf, "urdf"),
    (ExportWhat::Mjcf, "mjcf"),
    (ExportWhat::States, "states"),
    (ExportWhat::Grf, "grf"),
    (ExportWhat::Trc, "trc"),
    (ExportWhat::Gltf, "gltf"),
];

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum GenerateWhat {
    /// A parametric walk on a standard 21-joint skeleton.
    Walk,
}

/// Where the model and states come from: a take, or a robot with a states CSV.
#[derive(Debug, Args)]
pub struct SourceArgs {
    /// A BVH take.
    #[arg(conflicts_with_all = ["urdf", "dh"])]
    pub take: Option<PathBuf>,
    /// A URDF robot (fixed base).
    #[arg(long, conflicts_with = "dh")]
    pub urdf: Option<PathBuf>,
    /// A DH table (TOML, Robotics Toolbox conventions).
    #[arg(long)]
    pub dh: Option<PathBuf>,
    /// Gravity `x,y,z` (m/s²) for --urdf (default 0,0,-9.81: z up; a URDF exported from a
    /// Y-up take needs 0,-9.81,0, as its header comment says).
    #[arg(long, allow_hyphen_values = true)]
    pub gravity: Option<String>,
    /// The URDF's root link floats (a free joint to the world).
    #[arg(long)]
    pub floating: bool,
    /// States CSV (`time`, `q:<coord>`, `v:<coord>`, `a:<coord>`), as `export states` writes;
    /// `fd` needs no `a:` columns. Required with --urdf/--dh; with a take, replaces the take's
    /// own states.
    #[arg(long)]
    pub states: Option<PathBuf>,
}

/// How a take becomes a model and states.
#[derive(Debug, Args, Clone)]
pub struct TakeArgs {
    /// Length unit of the BVH: m, dm, cm, mm, in, cmu, or metres per unit. Default: detected.
    #[arg(long)]
    pub unit: Option<String>,
    /// Scale the skeleton to this rest-pose stature (m) instead of using a unit.
    #[arg(long, conflicts_with = "unit", allow_negative_numbers = true)]
    pub stature: Option<f64>,
    /// Up axis of the take: x, y or z. Default: detected.
    #[arg(long)]
    pub up: Option<String>,
    /// Position channels: add (to OFFSET), replace (OFFSET), or auto (per joint, from data;
    /// the default).
    #[arg(long)]
    pub positions: Option<String>,
    /// Joint model: euler (one revolute per channel, the paper's; the default) or ball.
    #[arg(long)]
    pub joints: Option<String>,
    /// Body mass (kg); default 75.
    #[arg(long, allow_negative_numbers = true)]
    pub mass: Option<f64>,
    /// Sex for the de Leva (1996) tables: male (default) or female.
    #[arg(long)]
    pub sex: Option<String>,
    /// Segment masses: regression (default: Zatsiorsky–Seluyanov, on body mass and the
    /// skeleton's stature) or fractions (de Leva's fixed fractions of body mass).
    #[arg(long)]
    pub segments: Option<String>,
    /// Link mass override `JOINT=KG` (repeatable); the other links are rescaled.
    #[arg(long = "link-mass", value_name = "JOINT=KG")]
    pub link_mass: Vec<String>,
    /// Smoothing: none, gaussian:<sigma s>, butterworth:<cutoff>hz (default butterworth:6hz).
    #[arg(long)]
    pub smooth: Option<String>,
    /// Joints to lock (comma-separated); their DOFs leave the model. `auto:TOL` (`auto:2%` of
    /// the outputs' peak, `auto:1nm`) locks every joint the take can do without within TOL on
    /// the knee moments of a human, every joint torque otherwise (docs/speed-accuracy.md).
    #[arg(long, value_delimiter = ',')]
    pub lock: Vec<String>,
    /// Keep only the subtree below this joint.
    #[arg(long)]
    pub subtree: Option<String>,
    /// Ground contact: auto (the default: feet when the take stands on a floor, none when it
    /// never touches one; the notes say which), feet (estimate ground reaction forces; an
    /// error on a take whose feet never touch a floor), or none.
    #[arg(long)]
    pub contact: Option<String>,
    /// Keep frame 0 even when it is a rest pose before the motion (dropped by default).
    #[arg(long)]
    pub keep_first_frame: bool,
    /// Position channels on joints below the body's root: weld (held at their mean, bones do
    /// not stretch; the default) or keep (a prismatic coordinate each).
    #[arg(long, value_name = "weld|keep")]
    pub joint_translations: Option<String>,
    /// Viscous joint friction b (N·m·s/rad; N·s/m on translations), τ gains b·q̇: `B` for every
    /// joint coordinate, `JOINT=B` for one joint's (or one coordinate's) (repeatable). Never on
    /// the 6 root coordinates of a floating avatar.
    #[arg(long, value_name = "B|JOINT=B", allow_negative_numbers = true)]
    pub damping: Vec<String>,
    /// Scene file (TOML, see data/scene_example.toml); flags given here override it.
    #[arg(long)]
    pub scene: Option<PathBuf>,
}

/// Residual reduction and the consistency summary (`id`, `anatomy`; with `--contact feet`).
#[derive(Debug, Args, Clone)]
pub struct ConsistencyArgs {
    /// Residual reduction, as OpenSim's RRA: on (adjust the trunk's mass centre and a smooth
    /// pelvis offset, within stated bounds, so that the root residuals fall within Hicks et
    /// al.'s 2015 thresholds; every output is then the adjusted model's and motion's) or off.
    /// Default: on for `anatomy` with ground contact, off for `id`. Needs ground contact
    /// (contact auto on a take that stands, or --contact feet).
    #[arg(long, value_name = "on|off")]
    pub consistent: Option<String>,
    /// Print a JSON summary on standard output (on standard error with `-o -`). `anatomy`: the
    /// consistency summary (keys thresholds, before, after, adjustments, meets, why,
    /// frames_beyond) instead of the table; without ground contact `{"contact": "none",
    /// "meets": null, "why": …}`. `id`: keys frames, ground_reactions, coordinates
    /// (peak |τ|, its time, RMS per coordinate, and whether they lie on frames whose ground
    /// force the feet cannot give), root_residual, contact_quality, consistency
    /// (the same summary, with contact), notes.
    #[arg(long)]
    pub json: bool,
}

impl ConsistencyArgs {
    /// Whether to reduce the residuals: `--consistent`, else `default`; `--consistent` refused
    /// without contact (`pipeline::commands::reduce_residuals`).
    fn reduce(&self, contact: bool, default: bool) -> Result<bool> {
        Ok(pipeline::commands::reduce_residuals(
            self.consistent.as_deref(),
            contact,
            default,
        )?)
    }
}

/// Computed-torque tracking settings.
#[derive(Debug, Args, Clone)]
pub struct SimArgs {
    /// euler, semi-implicit, rk4, dopri5[:tol].
    #[arg(long, default_value = "rk4")]
    pub integrator: String,
    /// Step (s).
    #[arg(long, default_value_t = 0.001, allow_negative_numbers = true)]
    pub dt: f64,
    /// Position gain Kp (1/s²): a number for every coordinate (default 400), or JOINT=X for one
    /// joint's coordinates or one coordinate (repeatable: --kp 400 --kp LeftLeg=900).
    #[arg(long, value_name = "X|JOINT=X", allow_negative_numbers = true)]
    pub kp: Vec<String>,
    /// Velocity gain Kv (1/s): a number (default 40) or JOINT=X, as --kp.
    #[arg(long, value_name = "X|JOINT=X", allow_negative_numbers = true)]
    pub kv: Vec<String>,
    /// Relative error of the controller's link masses (0.1 = 10 % heavy).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub mass_error: f64,
    /// Simulated time (s); default: the whole take.
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
}

impl TakeArgs {
    fn options(&self) -> Result<TakeOptions> {
        Ok(self.options_and_gains()?.0)
    }

    /// The flags as the library reads them (strings not yet validated).
    fn flags(&self) -> pipeline::Flags<'_> {
        pipeline::Flags {
            unit: self.unit.as_deref(),
            stature_m: self.stature,
            up: self.up.as_deref(),
            positions: self.positions.as_deref(),
            joints: self.joints.as_deref(),
            mass_kg: self.mass,
            sex: self.sex.as_deref(),
            segments: self.segments.as_deref(),
            link_mass: &self.link_mass,
            smooth: self.smooth.as_deref(),
            lock: &self.lock,
            subtree: self.subtree.as_deref(),
            contact: self.contact.as_deref(),
            keep_first_frame: self.keep_first_frame,
            damping: &self.damping,
            joint_translations: self.joint_translations.as_deref(),
        }
    }

    /// The take flags given (by their names on the command line).
    fn given(&self) -> Vec<&'static str> {
        self.flags().given()
    }

    /// [`Self::options`] for `command`, refusing a take flag it would ignore
    /// (`pipeline::flags::UNUSED_TAKE_FLAGS`).
    fn options_for(&self, command: &str) -> Result<TakeOptions> {
        self.refuse_unused(command)?;
        self.options()
    }

    /// [`Self::options_for`] `command` on `src`: a robot (`--urdf`, `--dh`) takes only `--damping`
    /// of the take flags, and a take whose states come from `--states` no smoothing.
    fn options_for_source(&self, command: &str, src: &SourceArgs) -> Result<TakeOptions> {
        self.refuse_unused(command)?;
        let robot = src.urdf.is_some() || src.dh.is_some();
        for flag in self.given() {
            if robot && flag != "--damping" {
                bail!(
                    "{flag} has no effect on a robot (--urdf, --dh): it describes how a BVH take \
                     becomes a model; remove it"
                );
            }
            if src.states.is_some() && flag == "--smooth" {
                bail!(
                    "--smooth has no effect with --states: the states file gives q, v and a as \
                     they are; smooth the take before `export states`, or drop --states"
                );
            }
        }
        self.options()
    }

    fn refuse_unused(&self, command: &str) -> Result<()> {
        Ok(pipeline::flags::refuse_unused(command, &self.given())?)
    }

    /// The take options (the scene's, then the flags over them) and the scene's gains, reading
    /// the scene file once.
    fn options_and_gains(&self) -> Result<(TakeOptions, Option<articula::io::scene::Gains>)> {
        Ok(pipeline::flags::options_from(
            self.scene.as_deref(),
            &self.flags(),
        )?)
    }
}

impl SourceArgs {
    fn source(&self) -> Result<ModelSource> {
        // the URDF's own settings mean nothing for a take or a DH table
        if self.urdf.is_none() {
            for (flag, given) in [
                ("--gravity", self.gravity.is_some()),
                ("--floating", self.floating),
            ] {
                if given {
                    bail!(
                        "{flag} has no effect without --urdf: a take's gravity is along its \
                         detected or given up axis (--up), a DH table's along -z, and both \
                         have their own base; remove it"
                    );
                }
            }
        }
        Ok(match (&self.take, &self.urdf, &self.dh) {
            (Some(t), None, None) => ModelSource::Take(t.clone()),
            (None, Some(u), None) => {
                let mut o = articula::model::urdf::UrdfOptions {
                    floating: self.floating,
                    ..Default::default()
                };
                if let Some(g) = &self.gravity {
                    let v: Vec<f64> = g
                        .split(',')
                        .map(|x| x.trim().parse::<f64>())
                        .collect::<Result<_, _>>()
                        .map_err(|_| anyhow::anyhow!("--gravity {g}: expected x,y,z in m/s²"))?;
                    let [x, y, z] = v[..] else {
                        bail!("--gravity {g}: expected three numbers x,y,z in m/s²");
                    };
                    o.gravity = nalgebra::Vector3::new(x, y, z);
                }
                ModelSource::Urdf(u.clone(), o)
            }
            (None, None, Some(d)) => ModelSource::Dh(d.clone()),
            _ => bail!("give a take (TAKE.bvh), --urdf FILE or --dh FILE"),
        })
    }
}

fn need(path: &Path) -> Result<()> {
    if !path.exists() {
        bail!("{}: no such file", path.display());
    }
    Ok(())
}

/// The bundled demo take, found beside the binary's sources (cargo run) or the working folder.
fn demo_take() -> PathBuf {
    let here = PathBuf::from("data/demo_walk.bvh");
    if here.exists() {
        return here;
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh")
}

pub fn run(cli: Cli) -> Result<ExitCode> {
    if let Some(n) = cli.threads {
        if n == 0 {
            bail!("--threads 0: expected 1 or more (1 is the serial path)");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("--threads: the thread pool")?;
    }
    let Some(cmd) = cli.cmd else {
        let files = if cli.files.is_empty() {
            vec![demo_take()]
        } else {
            cli.files
        };
        for f in &files {
            need(f)?;
        }
        let initial = files
            .into_iter()
            .map(|path| articula::session::Command::Load { path, name: None })
            .collect();
        articula::tui::run(initial).context("terminal UI")?;
        return Ok(ExitCode::SUCCESS);
    };
    match cmd {
        Cmd::Batch(args) => crate::batch::run(args),
        Cmd::Info(a) => commands::info(a),
        Cmd::Export(a) => commands::export(a),
        Cmd::Generate(a) => commands::generate(a),
        Cmd::Id(a) => commands::id(a),
        Cmd::Anatomy(a) => commands::anatomy(a),
        Cmd::Fd(a) => commands::fd(a),
        Cmd::MassMatrix(a) => commands::mass_matrix(a),
        Cmd::Simulate(a) => commands::simulate(a),
        Cmd::Bench(a) => commands::bench(a),
        Cmd::Tradeoff(a) => commands::tradeoff(a),
        Cmd::Smooth(a) => commands::smooth(a),
        Cmd::Blend(a) => commands::blend(a),
        Cmd::Run(a) => commands::run_session(a),
    }
}

/// `-o -` is standard output: the data, nothing else.
fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// A command's summary: on standard output, unless the data goes there (`-o -`), so that a
/// pipe gets only the data.
fn report(text: &str, output: Option<&Path>) {
    if output.is_some_and(is_stdout) {
        eprint!("{text}");
    } else {
        print!("{text}");
    }
}

/// The consistency summary: as JSON through [`report`], else the table on standard error.
fn print_consistency(
    c: &pipeline::consistency::Consistency,
    json: bool,
    output: &Path,
) -> Result<()> {
    if json {
        report(
            &format!("{}\n", serde_json::to_string_pretty(&c.json())?),
            Some(output),
        );
    } else {
        eprint!("{}", c.text());
    }
    Ok(())
}

/// The line that says where an output went, on standard error.
fn wrote(path: &Path) {
    if is_stdout(path) {
        eprintln!("wrote standard output");
    } else {
        eprintln!("wrote {}", path.display());
    }
}

/// A take's notes (what the pipeline changed or found: a dropped rest frame, a folded root, a
/// passage near gimbal lock, a capture glitch) on standard error, before the results.
fn print_notes(take: Option<&pipeline::Take>) {
    for n in take.iter().flat_map(|t| &t.notes) {
        eprintln!("note: {n}");
    }
}

/// Writes the sidecar `NAME.csv.json` of the CSV just written at `output` (none for `-` or a
/// device) and says so, with the take's `consistency` when its columns were computed with
/// ground contact; returns its path.
fn sidecar(
    output: &Path,
    command: &str,
    take: Option<&pipeline::Take>,
    model: Option<&articula::model::Model>,
    consistency: Option<&pipeline::consistency::Consistency>,
) -> Result<Option<PathBuf>> {
    let arguments: Vec<String> = std::env::args().skip(1).collect();
    let p = pipeline::summary::Provenance {
        command,
        arguments: &arguments,
        take,
        model,
        notes: &[],
        known_units: &[],
        consistency,
    };
    let written = pipeline::summary::write_sidecar(output, &p)?;
    if let Some(w) = &written {
        wrote(w);
    }
    Ok(written)
}

/// A `--json` summary through [`report`]: standard output, or standard error when the data
/// goes to standard output (`-o -`).
fn print_json(value: &impl serde::Serialize, output: &Path) -> Result<()> {
    report(
        &format!("{}\n", serde_json::to_string_pretty(value)?),
        Some(output),
    );
    Ok(())
}

/// `articula run --json`: the replay as JSON on standard output, also when it stops on an
/// error (then the error is returned after it, for the exit status and message).
fn run_json(session: &Path, out: &Path) -> Result<ExitCode> {
    let (report, result) = articula::tui::run_session_recorded(session, out);
    let j = report.json(session, result.as_ref().err());
    println!("{}", serde_json::to_string_pretty(&j)?);
    result?;
    Ok(ExitCode::SUCCESS)
}
