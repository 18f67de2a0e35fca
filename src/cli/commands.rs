//! One function per command of the command line: each reads its arguments, runs the
//! pipeline and says what it wrote.

use super::*;

pub(super) fn info(a: InfoArgs) -> Result<ExitCode> {
    let InfoArgs { take, opts, json } = a;
    let mut take = pipeline::load_take(&take, &opts.options_for("info")?)?;
    pipeline::resolve_contact(&mut take);
    let info = pipeline::info(&take);
    show(json, || info.json(), || info.text())?;
    Ok(ExitCode::SUCCESS)
}

pub(super) fn export(a: ExportArgs) -> Result<ExitCode> {
    let ExportArgs {
        what,
        take,
        opts,
        format,
        trc_units,
        json,
        output,
    } = a;
    let name = EXPORTS
        .iter()
        .find(|(w, _)| *w == what)
        .map_or("export", |e| e.1);
    let command = format!("export {name}");
    let mut take = pipeline::load_take(&take, &opts.options_for(&command)?)?;
    let extras = formats::export(
        &mut take,
        name,
        &output,
        format.as_deref(),
        trc_units.as_deref(),
    )?;
    let format = TableFormat::choose(&output, format.as_deref())?;
    let mut written = vec![output.clone()];
    if let Some(xml) = extras {
        print_notes(Some(&take));
        match xml {
            formats::ExternalLoadsXml::Written(xml) => {
                wrote(&xml);
                written.push(xml);
            }
            formats::ExternalLoadsXml::None(why) if format != TableFormat::Csv => {
                eprintln!("note: no ExternalLoads XML: {why}")
            }
            formats::ExternalLoadsXml::None(_) => {}
        }
    }
    let table = formats::EXPORTS.iter().any(|&(w, t)| w == name && t);
    if table && format == TableFormat::Csv {
        written.extend(sidecar(&output, &command, Some(&take), None, None)?);
    }
    wrote(&output);
    if json {
        let kind = match what {
            ExportWhat::Urdf => "urdf",
            ExportWhat::Mjcf => "mjcf",
            ExportWhat::Trc => "trc",
            ExportWhat::Gltf => "glb",
            _ => format.name(),
        };
        let motion = !matches!(what, ExportWhat::Urdf | ExportWhat::Mjcf);
        print_json(
            &pipeline::summary::WriteSummary::of_take(&command, &take, kind, &written, motion),
            &output,
        )?;
    }
    Ok(ExitCode::SUCCESS)
}

pub(super) fn generate(a: GenerateArgs) -> Result<ExitCode> {
    let GenerateArgs {
        what: GenerateWhat::Walk,
        output,
        fps,
        duration,
        scale,
    } = a;
    pipeline::generate_walk(&output, fps, duration, scale)?;
    wrote(&output);
    Ok(ExitCode::SUCCESS)
}

pub(super) fn id(a: IdArgs) -> Result<ExitCode> {
    let IdArgs {
        src,
        opts,
        consistency,
        format,
        grf,
        grf_offset,
        output,
    } = a;
    let format = TableFormat::choose(&output, format.as_deref())?;
    let o = opts.options_for_source("id", &src)?;
    let mut job = pipeline::load_source(&src.source()?, src.states.as_deref(), &o)?;
    if let Some(t) = job.take.as_mut() {
        pipeline::resolve_contact(t);
    }
    let contact = job
        .take
        .as_ref()
        .is_some_and(|t| t.options.contact == pipeline::Contact::Feet);
    let c = match &grf {
        Some(path) if consistency.consistent.is_none() => {
            need(path)?;
            pipeline::measured::use_measured_grf(&mut job, path, grf_offset.unwrap_or(0.0))?;
            None
        }
        Some(path) => {
            // residual reduction against the measured forces (the mass adjusted too)
            need(path)?;
            let take = job.take.as_ref().ok_or_else(|| {
                anyhow::anyhow!("--grf needs a take: ground reactions act on its feet")
            })?;
            let loads = pipeline::measured::measured_loads(take, path, grf_offset.unwrap_or(0.0))?;
            let reduce = consistency.reduce(true, false)?;
            let own = src.states.is_none();
            pipeline::consistency::consistent_job(&mut job, reduce, own, Some(&loads))?
        }
        None => {
            let reduce = consistency.reduce(contact, false)?;
            pipeline::consistency::consistent_job(&mut job, reduce, src.states.is_none(), None)?
        }
    };
    let mut outcome = formats::write_inverse_dynamics_as(&job, &output, format, c.as_ref())?;
    if format == TableFormat::Csv {
        sidecar(
            &output,
            "id",
            job.take.as_ref(),
            Some(&job.model),
            c.as_ref(),
        )?;
    }
    print_notes(job.take.as_ref());
    // the estimate's quality figure (how far the feet could give the needed force) says
    // nothing of measured forces: their residual columns do
    if let (Some(q), None) = (&outcome.quality, &grf) {
        eprintln!("{q}");
    }
    if let Some(c) = &c
        && !consistency.json
    {
        print_consistency(c, false, &output)?;
    }
    if consistency.json {
        outcome.summary.consistency = c.map(|c| c.json());
        print_json(&outcome.summary, &output)?;
    }
    wrote(&output);
    Ok(ExitCode::SUCCESS)
}

pub(super) fn anatomy(a: AnatomyArgs) -> Result<ExitCode> {
    let AnatomyArgs {
        take,
        opts,
        consistency,
        edges,
        gait,
        output,
    } = a;
    let include_edges = match edges.as_deref().map(str::trim) {
        None | Some("exclude") => false,
        Some("include") => true,
        Some(other) => bail!("--edges {other}: expected exclude or include"),
    };
    let o = pipeline::commands::anatomy_options(
        opts.options_for("anatomy")?,
        opts.scene.is_some() || opts.joints.is_some(),
    );
    let mut take = pipeline::load_take(&take, &o)?;
    pipeline::resolve_contact(&mut take);
    let contact = take.options.contact == pipeline::Contact::Feet;
    let reduce = consistency.reduce(contact, true)?;
    let mut a = pipeline::consistency::anatomy_consistent(&take, reduce)?;
    a.include_edges = include_edges;
    pipeline::anatomy::write_anatomy(&a, &output)?;
    sidecar(
        &output,
        "anatomy",
        Some(&take),
        None,
        a.consistency.as_ref(),
    )?;
    print_notes(Some(&take));
    for n in &a.notes {
        eprintln!("note: {n}");
    }
    eprint!("{}", pipeline::anatomy::summary(&a));
    if let Some(g) = &gait {
        let caption = articula::report::gait::take_caption(&take, reduce, a.consistency.as_ref());
        for n in articula::report::gait::write_gait(&a, &take, Some(&caption), g)? {
            eprintln!("note: {n}");
        }
        wrote(g);
    }
    if consistency.json {
        match &a.consistency {
            Some(c) => print_consistency(c, true, &output)?,
            None => print_json(&pipeline::commands::no_contact_json(&take), &output)?,
        }
    }
    wrote(&output);
    Ok(ExitCode::SUCCESS)
}

pub(super) fn fd(a: FdArgs) -> Result<ExitCode> {
    let FdArgs {
        src,
        opts,
        torques,
        output,
    } = a;
    // forward dynamics computes the accelerations: the states need only q and v
    let job = pipeline::load_source_with(
        &src.source()?,
        src.states.as_deref(),
        &opts.options_for_source("fd", &src)?,
        pipeline::StateColumns::QV,
    )?;
    pipeline::write_forward_dynamics(&job, &torques, &output)?;
    sidecar(&output, "fd", job.take.as_ref(), Some(&job.model), None)?;
    wrote(&output);
    Ok(ExitCode::SUCCESS)
}

pub(super) fn mass_matrix(a: MassMatrixArgs) -> Result<ExitCode> {
    let MassMatrixArgs { src, opts, output } = a;
    let job = pipeline::load_source(
        &src.source()?,
        src.states.as_deref(),
        &opts.options_for_source("mass-matrix", &src)?,
    )?;
    pipeline::write_mass_matrix(&job, &output)?;
    sidecar(
        &output,
        "mass-matrix",
        job.take.as_ref(),
        Some(&job.model),
        None,
    )?;
    wrote(&output);
    Ok(ExitCode::SUCCESS)
}

pub(super) fn simulate(a: SimulateArgs) -> Result<ExitCode> {
    let SimulateArgs {
        take,
        opts,
        sim,
        output,
        json,
    } = a;
    opts.refuse_unused("simulate")?;
    let (options, gains) = opts.options_and_gains()?;
    let take = pipeline::load_take(&take, &options)?;
    print_notes(Some(&take));
    // gains: the scene's (if any), then the flags over them
    let settings = pipeline::commands::sim_settings(
        &pipeline::commands::SimFlags {
            integrator: &sim.integrator,
            dt: sim.dt,
            kp: &sim.kp,
            kv: &sim.kv,
            mass_error: sim.mass_error,
            duration_s: sim.duration,
        },
        gains,
    )?;
    let summary = pipeline::simulate(&take, &settings, output.as_deref())?;
    if let Some(out) = &output {
        sidecar(out, "simulate", Some(&take), None, None)?;
    }
    let text = if json {
        format!("{}\n", serde_json::to_string_pretty(&summary.json())?)
    } else {
        summary.text()
    };
    report(&text, output.as_deref());
    Ok(ExitCode::SUCCESS)
}

pub(super) fn bench(a: BenchArgs) -> Result<ExitCode> {
    match a {
        BenchArgs {
            src,
            opts,
            json,
            edit: Some(edit),
            set,
            repeat,
            ..
        } => {
            let take = bench_take(&src, "--edit")?;
            let settings = articula::session::edit_bench::EditSettings::parse(
                &edit,
                &set,
                repeat.unwrap_or(5),
            )?;
            let r = articula::session::edit_bench::bench_edit(
                take,
                &opts.options_for_source("bench --edit", &src)?,
                &settings,
            )?;
            show(json, || r.json(), || r.text())?;
        }
        BenchArgs {
            src,
            opts,
            json,
            stages: true,
            repeat,
            minutes,
            ..
        } => {
            let take = bench_take(&src, "--stages")?;
            let settings = pipeline::StageSettings {
                repeat: repeat.unwrap_or(5),
                minutes,
            };
            let r = pipeline::bench_stages(
                take,
                &opts.options_for_source("bench --stages", &src)?,
                settings,
            )?;
            show(json, || r.json(), || r.text())?;
        }
        BenchArgs {
            src,
            opts,
            json,
            batches,
            repeat,
            ..
        } => {
            if repeat.is_some() {
                bail!("--repeat times --stages or --edit: give one of them, or drop --repeat");
            }
            let model =
                pipeline::load_model(&src.source()?, &opts.options_for_source("bench", &src)?)?;
            let r = pipeline::bench_batches(&model, batches)?;
            show(json, || r.json(), || r.text())?;
        }
    }
    Ok(ExitCode::SUCCESS)
}

pub(super) fn tradeoff(a: TradeoffArgs) -> Result<ExitCode> {
    match a {
        TradeoffArgs {
            take,
            opts,
            reduce: true,
            of,
            json,
            output,
            ..
        } => {
            let o = opts.options_for("tradeoff --reduce")?;
            if articula::pipeline::reduce::split_lock(&o.lock)?.0.is_some() {
                bail!(
                    "--lock auto:TOL reduces the model before --reduce would: give the joints \
                     to lock by name, or drop --reduce"
                );
            }
            let take = pipeline::load_take(&take, &o)?;
            print_notes(Some(&take));
            let r = pipeline::reduce::reduce(&take, (!of.is_empty()).then_some(&of[..]))?;
            let text = if json {
                format!("{}\n", serde_json::to_string_pretty(&r)?)
            } else {
                r.text()
            };
            report(&text, output.as_deref());
            if let Some(out) = output {
                r.write_csv(&out)?;
                sidecar(&out, "tradeoff --reduce", Some(&take), None, None)?;
                wrote(&out);
            }
        }
        TradeoffArgs {
            take,
            opts,
            duration,
            output,
            ..
        } => {
            let table = pipeline::tradeoff(&take, &opts.options_for("tradeoff")?, duration)?;
            report(&table.text(), output.as_deref());
            if let Some(out) = output {
                table.write_csv(&out)?;
                sidecar(&out, "tradeoff", None, None, None)?;
                wrote(&out);
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

pub(super) fn smooth(a: SmoothArgs) -> Result<ExitCode> {
    let SmoothArgs {
        take,
        opts,
        bvh_style,
        json,
        output,
    } = a;
    let style: articula::io::bvh::BvhStyle = bvh_style.parse()?;
    let take = pipeline::load_take(&take, &opts.options_for("smooth")?)?;
    pipeline::export_smoothed_bvh_as(&take, &output, style)?;
    wrote(&output);
    if json {
        let written = std::slice::from_ref(&output);
        let s = pipeline::summary::WriteSummary::of_take("smooth", &take, "bvh", written, true);
        print_json(&s, &output)?;
    }
    Ok(ExitCode::SUCCESS)
}

pub(super) fn blend(a: BlendArgs) -> Result<ExitCode> {
    let BlendArgs {
        takes,
        window,
        align,
        offset,
        time_scale,
        up,
        keep_first_frame,
        bvh_style,
        json,
        output,
    } = a;
    let up = up.map(|u| u.parse()).transpose()?;
    let style: articula::io::bvh::BvhStyle = bvh_style.parse()?;
    let notes = pipeline::blend_files(
        &takes,
        &window,
        &align,
        offset,
        time_scale,
        up,
        keep_first_frame,
        style,
        &output,
    )?;
    for n in &notes {
        eprintln!("{n}");
    }
    wrote(&output);
    if json {
        let s = pipeline::summary::WriteSummary {
            command: "blend".into(),
            takes: takes.iter().map(|t| t.display().to_string()).collect(),
            written: vec![output.display().to_string()],
            format: "bvh".into(),
            frames: None,
            frame_time_s: None,
            settings: Default::default(),
            notes,
        };
        print_json(&s, &output)?;
    }
    Ok(ExitCode::SUCCESS)
}

pub(super) fn run_session(a: RunArgs) -> Result<ExitCode> {
    let RunArgs { session, out, json } = a;
    need(&session)?;
    if json {
        return run_json(&session, &out);
    }
    let report = articula::tui::run_session(&session, &out)?;
    for m in &report.messages {
        println!("{m}");
    }
    println!(
        "{}: {} commands, {} expects passed, {} files written",
        session.display(),
        report.commands,
        report.expects,
        report.written.len()
    );
    Ok(ExitCode::SUCCESS)
}

/// Standard output: the JSON of a report with `--json`, else its text.
fn show(
    json: bool,
    value: impl FnOnce() -> serde_json::Value,
    text: impl FnOnce() -> String,
) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(&value())?);
    } else {
        print!("{}", text());
    }
    Ok(())
}

/// The take `bench FLAG` times (a BVH file that exists).
fn bench_take<'a>(src: &'a SourceArgs, flag: &str) -> Result<&'a Path> {
    let take = src
        .take
        .as_deref()
        .ok_or_else(|| anyhow::anyhow!("bench {flag} needs a take (a BVH file)"))?;
    need(take)?;
    Ok(take)
}
