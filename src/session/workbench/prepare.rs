//! [`Workbench::prepare`]: the [`Job`] of a long command, one function per kind of command.

use super::super::SessionError;
use super::super::command::{Command, RunKind};
use super::job::{Job, Task};
use super::{Workbench, err, is_csv, needs_results};
use std::path::Path;

/// A task and its label for progress displays.
type Prepared = (Task, String);

impl Workbench {
    /// The computation a long command needs (`run`, `load`, `scene`, `trajectory`, `blend`,
    /// `export`, `compare weights`, `report motor`, and an `expect` whose results are stale),
    /// to run on any thread; `None` for the commands that apply at once. Errors that need no
    /// computation (no take, an unknown joint) are found here.
    pub fn prepare(&self, cmd: &Command) -> Result<Option<Job>, SessionError> {
        let (task, label) = match cmd {
            Command::Run(kind) => self.prepare_run(*kind)?,
            Command::Load { path, name } => self.prepare_load(path, name.as_deref())?,
            Command::Scene { path } => (
                Task::Scene {
                    file: self.in_path(path),
                    in_dir: self.in_dir.clone(),
                },
                format!("scene {}", path.display()),
            ),
            Command::Trajectory {
                poses,
                duration_s,
                rate_hz,
            } => {
                let (index, poses) = self.check_trajectory(poses)?;
                let label = format!("trajectory of {}", self.takes[index].name);
                let task = Task::Trajectory {
                    index,
                    poses,
                    duration_s: *duration_s,
                    rate_hz: *rate_hz,
                };
                (task, label)
            }
            Command::Blend { a, b, window } => self.prepare_blend(a, b, *window)?,
            Command::Export { kind, path } => {
                let word = kind.word();
                let task = Task::Export {
                    kind: *kind,
                    out: self.out_path(path),
                };
                (task, format!("export {word} {}", path.display()))
            }
            Command::CompareWeights {
                masses,
                joint,
                path,
            } => self.prepare_compare(masses, joint.as_deref(), path)?,
            Command::ReportMotor { path, curves } => (
                Task::ReportMotor {
                    out: self.out_path(path),
                    curves: *curves,
                },
                format!("report motor {}", path.display()),
            ),
            Command::ReportGait { path } => (
                Task::ReportGait {
                    out: self.out_path(path),
                },
                format!("report gait {}", path.display()),
            ),
            Command::Expect(e)
                if needs_results(e) && self.take().is_some() && self.fresh_results().is_none() =>
            {
                let label = format!("inverse dynamics of {}", self.take_name()?);
                (Task::Then(Box::new(cmd.clone())), label)
            }
            _ => return Ok(None),
        };
        Ok(Some(self.job(task, label)))
    }

    /// The job of `task`, with a snapshot of what it reads.
    fn job(&self, task: Task, label: String) -> Job {
        Job {
            task,
            label,
            engine: self.engine.clone(),
            take: self.take().cloned(),
            params: self.params.clone(),
            fresh: self.fresh_results().cloned(),
            previous: self.latest_results().cloned(),
            sim: self
                .sim
                .as_ref()
                .filter(|(_, p)| p.same_results(&self.params))
                .map(|(r, _)| r.clone()),
            selection: self.selection.clone(),
            motor_classes: self.motor_classes.clone(),
        }
    }

    /// The active take's name, or the error of a command that needs one.
    fn take_name(&self) -> Result<String, SessionError> {
        self.take()
            .map(|t| t.name.clone())
            .ok_or_else(|| err("no take loaded (load PATH first)"))
    }

    /// `run id`, `run sim`.
    fn prepare_run(&self, kind: RunKind) -> Result<Prepared, SessionError> {
        let name = self.take_name()?;
        let label = match kind {
            RunKind::Id => format!("inverse dynamics of {name}"),
            RunKind::Sim => format!("simulation of {name}"),
        };
        Ok((Task::Run(kind), label))
    }

    /// `load PATH [as NAME]`: a take, a robot, or (`.csv`) the active robot's motion.
    fn prepare_load(&self, path: &Path, name: Option<&str>) -> Result<Prepared, SessionError> {
        let file = self.in_path(path);
        let label = format!("loading {}", path.display());
        if is_csv(path) {
            let (index, model) = self.active_robot("load STATES.csv")?;
            return Ok((Task::Motion { file, index, model }, label));
        }
        let name = name.map(str::to_string).or_else(|| self.second_name(&file));
        Ok((Task::Load { file, name }, label))
    }

    /// `blend A B T0:T1` of two loaded takes.
    fn prepare_blend(
        &self,
        a: &str,
        b: &str,
        window: (f64, f64),
    ) -> Result<Prepared, SessionError> {
        let find = |n: &str| {
            self.takes
                .iter()
                .find(|t| t.name == *n)
                .cloned()
                .ok_or_else(|| err(format!("no take called '{n}'")))
        };
        let task = Task::Blend {
            a: Box::new(find(a)?),
            b: Box::new(find(b)?),
            window,
        };
        Ok((task, format!("blend {a} {b}")))
    }

    /// `compare weights M1,M2,… PATH [joint J]` of the selection or of joint `J`.
    fn prepare_compare(
        &self,
        masses: &[f64],
        joint: Option<&str>,
        path: &Path,
    ) -> Result<Prepared, SessionError> {
        let coord = match joint {
            Some(j) => self.resolve_coord(j)?,
            None => self
                .selection
                .clone()
                .ok_or_else(|| err("compare weights: select a joint or give joint J"))?,
        };
        self.take_name()?;
        let label = format!(
            "compare weights {} kg",
            masses
                .iter()
                .map(|m| m.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
        let task = Task::Compare {
            masses: masses.to_vec(),
            coord,
            out: self.out_path(path),
        };
        Ok((task, label))
    }
}
