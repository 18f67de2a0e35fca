//! `articula batch`: one take command over many takes (and a sweep of settings), each run as a
//! child process of this same executable, N at a time (largest takes first), with a summary table.
//!
//! This lives in the binary beside `cli.rs`, not in the library: it spawns processes, reads the
//! clock and draws a progress bar, none of which the library's pure layers do. A child process
//! per take isolates a crash (a panic, an abort, a diverged simulation) to its row.
//!
//! Stages: expand the inputs into takes → cross them with the `--vary` settings → run each job
//! (or skip it when its output is up to date) → read each output back for its figures → write
//! `summary.csv` (and `--json` on standard output).

use anyhow::{Context, Result, bail};
use articula::report::csv::{read_columns, write_table};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::{ExitCode, Stdio};
use std::time::{Instant, SystemTime};

/// `articula batch INPUT… -o DIR [options] [--] COMMAND [command options]` (the `--` may be left
/// out: [`with_command_separator`]).
#[derive(Debug, Args)]
pub struct BatchArgs {
    /// Takes: folders (every .bvh below, recursively, sorted), files, or `@LIST` (a file of
    /// paths, one a line, relative to the list's folder; `#` starts a comment).
    #[arg(required = true, value_name = "INPUT")]
    pub inputs: Vec<String>,
    /// Output folder: each take's output and log under its path relative to its input folder,
    /// and `summary.csv`.
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Takes run at once (default: every core).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Redo takes whose outputs are up to date.
    #[arg(long)]
    pub force: bool,
    /// Print the summary as JSON (an array of rows) on standard output.
    #[arg(long)]
    pub json: bool,
    /// Sweep a command flag: `KEY=V1,V2,…` passes `--KEY V` (repeatable; the cross product of
    /// all runs, one output and one summary row per take × setting).
    #[arg(long, value_name = "KEY=V1,V2")]
    pub vary: Vec<String>,
    /// Output columns whose peak |x| and RMS the summary gives (default: anatomy's knee flexion
    /// moments, id's root residuals).
    #[arg(long, value_name = "COL1,COL2", value_delimiter = ',')]
    pub of: Vec<String>,
    /// The take command and its options, after `--`: `id`, `anatomy`, `simulate`, `smooth`,
    /// `mass-matrix`, `export states|positions|urdf|mjcf|grf|trc`, `info`.
    #[arg(last = true, required = true, value_name = "COMMAND")]
    pub command: Vec<String>,
}

/// The command line with `--` put before a batch's take command when the user left it out
/// (`articula batch takes/ -o out/ id --contact auto`, as the issue writes it): the first
/// argument after `batch` and at least one input that names a take command (`id`, `export`,
/// …), is not an existing path and is not the value of a batch option. Any other command
/// line is returned as it was.
pub fn with_command_separator(args: Vec<std::ffi::OsString>) -> Vec<std::ffi::OsString> {
    let b = 1;
    if args.get(b).is_none_or(|a| a != "batch") {
        return args;
    }
    if args[b..].iter().any(|a| a == "--") {
        return args;
    }
    const VALUED: [&str; 5] = ["-o", "--output", "--jobs", "--vary", "--of"];
    let mut inputs = 0;
    let mut at = None;
    let mut k = b + 1;
    while k < args.len() {
        let a = args[k].to_string_lossy();
        if VALUED.contains(&a.as_ref()) {
            k += 2;
            continue;
        }
        if a.starts_with('-') {
            k += 1;
            continue;
        }
        let command = COMMANDS.iter().any(|c| c.words[0] == a) || a == "info";
        if command && inputs > 0 && !Path::new(a.as_ref()).exists() {
            at = Some(k);
            break;
        }
        inputs += 1;
        k += 1;
    }
    let mut args = args;
    if let Some(k) = at {
        args.insert(k, "--".into());
    }
    args
}

/// How the output of a take command is named and read back.
struct CommandSpec {
    /// The command's words before the take (`export states`).
    words: &'static [&'static str],
    /// Extension of its output.
    ext: &'static str,
    /// The output is the child's standard output (`info --json`), not a `-o FILE`.
    stdout: bool,
    /// Columns summarised when `--of` is not given (those present in the output).
    default_of: &'static [&'static str],
}

const RESIDUALS: &[&str] = &[
    "residual:fx",
    "residual:fy",
    "residual:fz",
    "residual:tx",
    "residual:ty",
    "residual:tz",
];

/// Every take command batch can run: one row each.
const COMMANDS: &[CommandSpec] = &[
    CommandSpec {
        words: &["id"],
        ext: "csv",
        stdout: false,
        default_of: RESIDUALS,
    },
    CommandSpec {
        words: &["anatomy"],
        ext: "csv",
        stdout: false,
        default_of: &["moment:knee_l:flexion", "moment:knee_r:flexion"],
    },
    CommandSpec {
        words: &["simulate"],
        ext: "csv",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["smooth"],
        ext: "bvh",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["mass-matrix"],
        ext: "csv",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["export", "states"],
        ext: "csv",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["export", "positions"],
        ext: "csv",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["export", "urdf"],
        ext: "urdf",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["export", "mjcf"],
        ext: "xml",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["export", "gltf"],
        ext: "glb",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["export", "grf"],
        ext: "csv",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["export", "trc"],
        ext: "trc",
        stdout: false,
        default_of: &[],
    },
    CommandSpec {
        words: &["info"],
        ext: "json",
        stdout: true,
        default_of: &[],
    },
];

/// One take found in the inputs.
struct Take {
    path: PathBuf,
    /// Path relative to its input folder (the file name for a file given directly).
    rel: PathBuf,
}

/// One run: a take under one setting of the swept flags.
struct Job<'a> {
    take: &'a Take,
    setting: Vec<(String, String)>,
    output: PathBuf,
    log: PathBuf,
    sidecar: PathBuf,
    argv: Vec<String>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Status {
    Ok,
    Failed,
    Skipped,
}

impl Status {
    fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
            Status::Skipped => "skipped",
        }
    }
}

/// One summary row.
struct Row {
    take: String,
    setting: Vec<(String, String)>,
    status: Status,
    /// Wall time of the child (s); 0 when skipped.
    wall_time: f64,
    /// Rows of the output CSV (frames of `info`), when there is one.
    frames: Option<usize>,
    /// Peak |x| and RMS per summarised column present in the output.
    figures: Vec<(String, f64, f64)>,
    output: PathBuf,
    failure: String,
}

pub fn run(args: BatchArgs) -> Result<ExitCode> {
    // the command: which one, and what passes through
    let spec = COMMANDS
        .iter()
        .find(|c| {
            args.command.len() >= c.words.len()
                && c.words.iter().zip(&args.command).all(|(w, a)| w == a)
        })
        .with_context(|| {
            let names: Vec<String> = COMMANDS.iter().map(|c| c.words.join(" ")).collect();
            format!(
                "batch -- {}: not a take command batch can run; expected one of: {}",
                args.command.join(" "),
                names.join(", ")
            )
        })?;
    let passthrough = &args.command[spec.words.len()..];
    if let Some(a) = passthrough
        .iter()
        .find(|a| *a == "-o" || a.starts_with("--output") || a.starts_with("-o"))
    {
        bail!("batch -- {a}: batch names each output itself under -o DIR; remove it");
    }
    let settings = sweep(&args.vary)?;
    let of: Vec<String> = if args.of.is_empty() {
        spec.default_of.iter().map(|s| s.to_string()).collect()
    } else {
        args.of.clone()
    };

    // the takes, and one job per take × setting
    let takes = expand_inputs(&args.inputs)?;
    if takes.is_empty() {
        bail!(
            "batch: no takes found in {} (folders are searched for .bvh files)",
            args.inputs.join(" ")
        );
    }
    let jobs = plan(&takes, &settings, spec, passthrough, &args.output)?;

    // run them, N at a time, each in a child process
    let threads = args.jobs.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    if threads == 0 {
        bail!("--jobs 0: give at least 1");
    }
    // the cores are shared out among the takes running at once: each child's frames run on
    // cores / N threads (its own `--threads` wins), so N takes do not each ask for every core
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let child_threads = (cores / threads.min(jobs.len()).max(1)).max(1);
    let progress = Progress::new(jobs.len());
    let rows = run_all(&jobs, threads, |job| {
        let row = run_job(job, spec, &of, args.force, child_threads);
        progress.done(&row);
        row
    });
    progress.finish();

    // the summary
    let summary = args.output.join("summary.csv");
    let (header, cells) = summary_table(&rows, &settings, &of);
    write_table(&summary, &header, &cells)?;
    summary_sidecar(&summary, &rows);
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&summary_json(&header, &cells))?
        );
    }
    let count = |s: Status| rows.iter().filter(|r| r.status == s).count();
    let failed = count(Status::Failed);
    eprintln!(
        "batch: {} ok, {} skipped, {failed} failed; wrote {}",
        count(Status::Ok),
        count(Status::Skipped),
        summary.display()
    );
    Ok(if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// Runs `work` on every job from `threads` worker threads, the largest takes first (longest
/// processing time first: a big take started last would leave the other workers idle while it
/// runs alone), and returns the rows in the jobs' order.
fn run_all(jobs: &[Job], threads: usize, work: impl Fn(&Job) -> Row + Sync) -> Vec<Row> {
    use std::sync::Mutex;
    use std::sync::atomic::{AtomicUsize, Ordering};
    // the queue: job indices by take size, largest first (stable: ties keep their order)
    let size = |j: &Job| std::fs::metadata(&j.take.path).map_or(0, |m| m.len());
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(size(&jobs[i])));
    let next = AtomicUsize::new(0);
    let rows: Mutex<Vec<Option<Row>>> = Mutex::new((0..jobs.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..threads.min(jobs.len()) {
            scope.spawn(|| {
                while let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let row = work(&jobs[i]);
                    rows.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(row);
                }
            });
        }
    });
    rows.into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .flatten()
        .collect()
}

/// The settings of the sweep: the cross product of every `KEY=V1,V2,…` (one empty setting
/// without `--vary`).
fn sweep(vary: &[String]) -> Result<Vec<Vec<(String, String)>>> {
    let mut settings = vec![Vec::new()];
    for v in vary {
        let Some((key, values)) = v.split_once('=') else {
            bail!("--vary {v}: expected KEY=V1,V2 (e.g. mass=60,80,100)");
        };
        let key = key.trim().trim_start_matches("--");
        let values: Vec<&str> = values
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        if key.is_empty() || values.is_empty() {
            bail!("--vary {v}: expected KEY=V1,V2 (e.g. mass=60,80,100)");
        }
        settings = settings
            .into_iter()
            .flat_map(|s| {
                values.iter().map(move |val| {
                    let mut s = s.clone();
                    s.push((key.to_string(), val.to_string()));
                    s
                })
            })
            .collect();
    }
    Ok(settings)
}

/// The takes named by the inputs: folders searched recursively for `.bvh` (sorted), files as
/// given, `@LIST` files read line by line.
fn expand_inputs(inputs: &[String]) -> Result<Vec<Take>> {
    let mut takes = Vec::new();
    for input in inputs {
        if let Some(list) = input.strip_prefix('@') {
            let list = Path::new(list);
            let text = std::fs::read_to_string(list)
                .with_context(|| format!("batch: reading the list {}", list.display()))?;
            let base = list.parent().unwrap_or(Path::new(""));
            for line in text.lines() {
                let line = line.split('#').next().unwrap_or("").trim();
                if !line.is_empty() {
                    add_input(&base.join(line), &mut takes)?;
                }
            }
        } else {
            add_input(Path::new(input), &mut takes)?;
        }
    }
    Ok(takes)
}

fn add_input(path: &Path, takes: &mut Vec<Take>) -> Result<()> {
    if path.is_dir() {
        let mut found = Vec::new();
        bvh_below(path, &mut found)?;
        found.sort();
        for p in found {
            let rel = p.strip_prefix(path).unwrap_or(&p).to_path_buf();
            takes.push(Take { path: p, rel });
        }
    } else {
        // a file (or a missing one: its child reports it, as a failed row)
        let rel = PathBuf::from(path.file_name().unwrap_or(path.as_os_str()));
        takes.push(Take {
            path: path.to_path_buf(),
            rel,
        });
    }
    Ok(())
}

fn bvh_below(dir: &Path, found: &mut Vec<PathBuf>) -> Result<()> {
    let entries =
        std::fs::read_dir(dir).with_context(|| format!("batch: reading {}", dir.display()))?;
    for e in entries {
        let p = e
            .with_context(|| format!("batch: reading {}", dir.display()))?
            .path();
        if p.is_dir() {
            bvh_below(&p, found)?;
        } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("bvh")) {
            found.push(p);
        }
    }
    Ok(())
}

/// One job per take × setting, with its output, log and sidecar paths and the child's argv.
fn plan<'a>(
    takes: &'a [Take],
    settings: &[Vec<(String, String)>],
    spec: &CommandSpec,
    passthrough: &[String],
    dir: &Path,
) -> Result<Vec<Job<'a>>> {
    // the output's extension: the command's own, or the table format asked for (`--format sto`)
    let ext = passthrough
        .iter()
        .position(|a| a == "--format")
        .and_then(|i| passthrough.get(i + 1))
        .map(String::as_str)
        .or_else(|| passthrough.iter().find_map(|a| a.strip_prefix("--format=")))
        .unwrap_or(spec.ext);
    let mut jobs = Vec::new();
    let mut seen = std::collections::HashMap::new();
    for take in takes {
        for setting in settings {
            // DIR/<relative path without .bvh>__key=value….<ext>
            let suffix: String = setting
                .iter()
                .map(|(k, v)| format!("__{k}={}", v.replace(['/', '\\'], "_")))
                .collect();
            let stem = take.rel.with_extension("");
            let name = format!("{}{suffix}", stem.display());
            let take_ext = take
                .rel
                .extension()
                .map_or("bvh".into(), |e| e.to_string_lossy().into_owned());
            let output = dir.join(format!("{name}.{}", ext));
            if let Some(other) = seen.insert(output.clone(), take.path.clone()) {
                bail!(
                    "batch: {} and {} would both write {}; give their folder instead of the \
                     files, or rename one",
                    other.display(),
                    take.path.display(),
                    output.display()
                );
            }
            let log = dir.join(format!("{name}.{take_ext}.log"));
            let sidecar = dir.join(".batch").join(format!("{name}.args"));

            // argv: COMMAND TAKE passthrough --KEY V … [-o OUT | --json]
            let mut argv: Vec<String> = spec.words.iter().map(|w| w.to_string()).collect();
            argv.push(take.path.to_string_lossy().into_owned());
            argv.extend(passthrough.iter().cloned());
            for (k, v) in setting {
                argv.push(format!("--{k}"));
                argv.push(v.clone());
            }
            if spec.stdout {
                if !argv.iter().any(|a| a == "--json") {
                    argv.push("--json".into());
                }
            } else {
                argv.push("-o".into());
                argv.push(output.to_string_lossy().into_owned());
            }
            jobs.push(Job {
                take,
                setting: setting.clone(),
                output,
                log,
                sidecar,
                argv,
            });
        }
    }
    Ok(jobs)
}

/// Runs one job (or skips it when up to date), then reads its output back for the summary.
fn run_job(job: &Job, spec: &CommandSpec, of: &[String], force: bool, threads: usize) -> Row {
    let mut row = Row {
        take: job.take.rel.to_string_lossy().into_owned(),
        setting: job.setting.clone(),
        status: Status::Ok,
        wall_time: 0.0,
        frames: None,
        figures: Vec::new(),
        output: job.output.clone(),
        failure: String::new(),
    };
    if !force && up_to_date(job) {
        row.status = Status::Skipped;
    } else {
        let start = Instant::now();
        let result = execute(job, spec, threads);
        row.wall_time = start.elapsed().as_secs_f64();
        if let Err(e) = result {
            row.status = Status::Failed;
            row.failure = e;
            return row;
        }
    }
    read_back(&mut row, of);
    row
}

/// The output exists, is newer than the take, and was made with the same arguments.
fn up_to_date(job: &Job) -> bool {
    let (Some(out), Some(take)) = (modified(&job.output), modified(&job.take.path)) else {
        return false;
    };
    out >= take
        && std::fs::read_to_string(&job.sidecar).is_ok_and(|recorded| recorded == args_text(job))
}

/// What the sidecar records: the version of articula that made the output (a comment line,
/// so that a new version redoes what an older one computed), then the child's arguments, one a
/// line.
fn args_text(job: &Job) -> String {
    let version = format!("# articula {}\n", env!("CARGO_PKG_VERSION"));
    std::iter::once(version)
        .chain(job.argv.iter().map(|a| format!("{a}\n")))
        .collect()
}

/// Runs the child; its output in place, its log written, its sidecar recorded on success. The
/// error is the last line of its standard error.
fn execute(job: &Job, spec: &CommandSpec, threads: usize) -> std::result::Result<(), String> {
    for p in [&job.output, &job.log, &job.sidecar] {
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("creating {}: {e}", parent.display()))?;
        }
    }
    // a stale sidecar must not vouch for an output this run fails to replace
    let _ = std::fs::remove_file(&job.sidecar);
    let exe = std::env::current_exe().map_err(|e| format!("finding articula itself: {e}"))?;
    let out = std::process::Command::new(exe)
        .args(&job.argv)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("starting articula: {e}"))?;

    // the log: standard output, then standard error
    let mut log = out.stdout.clone();
    log.extend_from_slice(&out.stderr);
    articula::io::write_atomic(&job.log, &log).map_err(|e| e.to_string())?;

    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let last = stderr.lines().rev().find(|l| !l.trim().is_empty());
        return Err(match (last, out.status.code()) {
            (Some(l), _) => {
                let l = l.trim();
                l.strip_prefix("articula: error: ").unwrap_or(l).to_string()
            }
            (None, Some(c)) => format!("exit status {c}"),
            (None, None) => "killed by a signal".into(),
        });
    }
    if spec.stdout {
        articula::io::write_atomic(&job.output, &out.stdout).map_err(|e| e.to_string())?;
    } else if !job.output.exists() {
        return Err(format!("no output written at {}", job.output.display()));
    }
    articula::io::write_atomic(&job.sidecar, args_text(job).as_bytes()).map_err(|e| e.to_string())
}

/// Frames and figures from the output: a CSV's rows and the peak |x| and RMS of the columns
/// asked for; `info`'s `frames`.
fn read_back(row: &mut Row, of: &[String]) {
    match row
        .output
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
    {
        "csv" => match read_columns(&row.output) {
            Ok((header, columns)) => {
                row.frames = columns.first().map(Vec::len);
                for name in of {
                    if let Some(c) = header.iter().position(|h| h == name) {
                        let (peak, rms) = articula::pipeline::table::peak_rms(&columns[c]);
                        row.figures.push((name.clone(), peak, rms));
                    }
                }
            }
            Err(e) => {
                row.status = Status::Failed;
                row.failure = format!("reading the output back: {e}");
            }
        },
        "json" => {
            row.frames = std::fs::read_to_string(&row.output)
                .ok()
                .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
                .and_then(|v| v.get("frames")?.as_u64())
                .map(|n| n as usize);
        }
        _ => {}
    }
}

/// The summary's header and cells: take, the swept keys (`setting:<key>`), status, wall time,
/// frames, peak and RMS of each summarised column present in some output, output, failure.
fn summary_table(
    rows: &[Row],
    settings: &[Vec<(String, String)>],
    of: &[String],
) -> (Vec<String>, Vec<Vec<String>>) {
    let keys: Vec<String> = settings
        .first()
        .map(|s| s.iter().map(|(k, _)| k.clone()).collect())
        .unwrap_or_default();
    let figures: Vec<&String> = of
        .iter()
        .filter(|c| rows.iter().any(|r| r.figures.iter().any(|f| &f.0 == *c)))
        .collect();
    // the column scheme (docs/formats.md): a swept flag is `setting:<flag>`
    let mut header = vec!["take".to_string()];
    header.extend(keys.iter().map(|k| format!("setting:{k}")));
    header.extend(["status", "wall_time", "frames"].map(String::from));
    for c in &figures {
        header.push(format!("peak:{c}"));
        header.push(format!("rms:{c}"));
    }
    header.extend(["output", "failure"].map(String::from));

    let number = articula::io::shortest::shortest;
    let cells = rows
        .iter()
        .map(|r| {
            let mut cells = vec![r.take.clone()];
            cells.extend(r.setting.iter().map(|(_, v)| v.clone()));
            cells.push(r.status.name().into());
            cells.push(format!("{:.3}", r.wall_time));
            cells.push(r.frames.map(|n| n.to_string()).unwrap_or_default());
            for c in &figures {
                match r.figures.iter().find(|f| &f.0 == *c) {
                    Some(&(_, peak, rms)) => cells.extend([number(peak), number(rms)]),
                    None => cells.extend([String::new(), String::new()]),
                }
            }
            cells.push(r.output.to_string_lossy().into_owned());
            cells.push(r.failure.clone());
            cells
        })
        .collect();
    (header, cells)
}

/// The sidecar `summary.csv.json` (docs/formats.md), through the one sidecar writer: the units
/// of `peak:<column>` and `rms:<column>` are those the outputs' own sidecars give `<column>`
/// (a coordinate's unit needs its model, which only the children loaded). A summary it cannot
/// describe (an output without a sidecar naming a coordinate's column) is said on standard
/// error; the batch's results stand.
fn summary_sidecar(summary: &Path, rows: &[Row]) {
    let mut known: Vec<(String, String)> = Vec::new();
    for r in rows.iter().filter(|r| !r.figures.is_empty()) {
        let Some(path) = articula::report::sidecar::path_for(&r.output) else {
            continue;
        };
        let Some(side) = std::fs::read_to_string(&path)
            .ok()
            .and_then(|t| serde_json::from_str::<articula::report::sidecar::Sidecar>(&t).ok())
        else {
            continue;
        };
        for c in side.columns {
            if !known.iter().any(|(n, _)| *n == c.name) {
                known.push((c.name, c.unit));
            }
        }
    }
    let arguments: Vec<String> = std::env::args().skip(1).collect();
    let p = articula::pipeline::summary::Provenance {
        command: "batch",
        arguments: &arguments,
        take: None,
        model: None,
        notes: &[],
        known_units: &known,
        consistency: None,
    };
    if let Err(e) = articula::pipeline::summary::write_sidecar(summary, &p) {
        eprintln!("batch: {} has no sidecar: {e}", summary.display());
    }
}

/// The summary as JSON: the rows of `summary.csv`, one object per row under the CSV's own
/// column names (so `pandas.DataFrame(json)` and `read_csv` give the same table). Figures,
/// `wall_time` and `frames` are numbers, an empty cell is null; the rest are strings.
fn summary_json(header: &[String], cells: &[Vec<String>]) -> serde_json::Value {
    use serde_json::{Map, Value};
    let numeric = |key: &str| {
        matches!(key, "wall_time" | "frames") || key.starts_with("peak:") || key.starts_with("rms:")
    };
    let value = |key: &str, cell: &str| match cell {
        "" if numeric(key) => Value::Null,
        _ if numeric(key) => match cell.parse::<u64>() {
            Ok(n) => Value::from(n),
            Err(_) => cell.parse::<f64>().ok().map_or(Value::Null, Value::from),
        },
        _ => Value::String(cell.to_string()),
    };
    let list = cells
        .iter()
        .map(|row| {
            let o: Map<String, Value> = header
                .iter()
                .zip(row)
                .map(|(k, c)| (k.clone(), value(k, c)))
                .collect();
            Value::Object(o)
        })
        .collect();
    Value::Array(list)
}

/// A progress bar on a terminal (takes done/total, frames/s, ETA); one plain line per take
/// otherwise.
struct Progress {
    bar: Option<ProgressBar>,
    total: usize,
    done: std::sync::atomic::AtomicUsize,
    frames: std::sync::atomic::AtomicUsize,
    start: Instant,
}

impl Progress {
    fn new(total: usize) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(total as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:30} {pos}/{len} takes  {msg}  {elapsed_precise} ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar
        });
        Progress {
            bar,
            total,
            done: 0.into(),
            frames: 0.into(),
            start: Instant::now(),
        }
    }

    fn done(&self, row: &Row) {
        use std::sync::atomic::Ordering::Relaxed;
        let n = self.done.fetch_add(1, Relaxed) + 1;
        // frames/s of the takes run (a skipped take costs nothing)
        let ran = match row.status {
            Status::Ok => row.frames.unwrap_or(0),
            _ => 0,
        };
        let frames = self.frames.fetch_add(ran, Relaxed) + ran;
        let rate = frames as f64 / self.start.elapsed().as_secs_f64().max(1e-9);
        let setting: String = row
            .setting
            .iter()
            .map(|(k, v)| format!(" {k}={v}"))
            .collect();
        let what = format!("{}{setting}", row.take);
        match &self.bar {
            Some(bar) => {
                bar.set_message(format!("{rate:.0} frames/s"));
                if row.status == Status::Failed {
                    bar.println(format!("failed {what}: {}", row.failure));
                }
                bar.inc(1);
            }
            None => {
                let tail = match row.status {
                    Status::Failed => format!(": {}", row.failure),
                    _ => format!(" ({:.2} s)", row.wall_time),
                };
                eprintln!("[{n}/{}] {} {what}{tail}", self.total, row.status.name());
            }
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// When a file was last written, if it exists.
fn modified(p: &Path) -> Option<SystemTime> {
    std::fs::metadata(p).and_then(|m| m.modified()).ok()
}
