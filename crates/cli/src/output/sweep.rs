//! The summaries of sweeps, merges, plans, comparisons and checks.

use std::path::Path;

use quakejoint_model::validity::Flags;
use serde_json::json;

/// `quakejoint sweep`.
///
/// `next` continues an interrupted sweep; `retry` runs its failed jobs again.
pub fn sweep_summary(
    s: &quakejoint_sweep::Summary,
    next: Option<&crate::continuation::Next>,
    retry: Option<&crate::continuation::Next>,
    json: bool,
) {
    // a bridge given by its modes sweeps period scales, not periods
    let axis = if s.modal { "period_scale" } else { "period" };
    let at = |z: f64, t: f64| if s.modal { format!("period scale {t}") } else { format!("damping {z} / T {t:.4} s") };
    if json {
        let failures: Vec<_> = s
            .failed
            .iter()
            .map(|(case, record, z, t, msg)| json!({"case": case, "record": record, "damping": z, axis: t, "message": msg}))
            .collect();
        let v = json!({
            "output": s.output.display().to_string(),
            "journal": s.journal.display().to_string(),
            "jobs": s.jobs,
            "resumed": s.resumed,
            "retried": s.retried,
            "ran": s.ran,
            "not_run": s.not_run,
            "complete": s.not_run == 0,
            "interrupted": s.interrupted,
            "failed": s.failed.len(),
            "failures": failures,
            "flagged": s.flagged.len(),
            "flag_counts": flag_counts(&s.flagged),
            "flagged_jobs": s.flagged.iter().map(|(case, record, z, t, bits, findings)| json!({
                "case": case, "record": record, "damping": z, axis: t,
                "validity": bits, "flags": Flags(*bits).names(), "findings": findings,
            })).collect::<Vec<_>>(),
            "pounded": s.pounded,
            "peak_contact_force": s.peak_contact.as_ref().map(|p| p.0),
            "fuses": json!({ "jobs": s.fuses[0], "broken": s.fuses[1], "stroke_exhausted": s.fuses[2] }),
            "notices": s.notices,
            "continue_command": next.map(|n| &n.command),
            "retry_command": retry.map(|n| &n.command),
            "wall_time_s": s.wall_time_s,
            "peak_memory_mb": s.peak_memory_mb,
            "fragility": s.fragility.as_ref().map(|(f, rows)| fragility_json(f, rows)),
            "design": s.design.iter().map(design_json).collect::<Vec<_>>(),
        });
        out!("{v}");
        return;
    }
    let mut state = if s.interrupted {
        "interrupted"
    } else if s.ran == 0 && s.not_run == 0 {
        "already complete"
    } else {
        "complete"
    }
    .to_string();
    if !s.interrupted && !s.failed.is_empty() {
        // never just "complete" while jobs wait to be retried
        state += &format!(", but {} of its jobs failed", s.failed.len());
    }
    let retried = if s.retried > 0 { format!(", {} failed jobs retried", s.retried) } else { String::new() };
    out!(
        "sweep {state}: {} of {} jobs done ({} from the journal{retried}, {} run now) in {:.1} s -> {}",
        s.jobs - s.not_run,
        s.jobs,
        s.resumed,
        s.ran,
        s.wall_time_s,
        s.output.display()
    );
    impact_lines(s, &at);
    if let Some(mb) = s.peak_memory_mb {
        out!("peak memory: {mb:.0} MB");
    }
    match &s.fragility {
        // a shard holds part of every stripe: its curves are not the sweep's
        Some(_) if s.shard.is_some() => {
            out!("fragility: fitted on every stripe's runs once the shards are merged (`quakejoint merge`)")
        }
        Some((f, rows)) => {
            out!("{}", quakejoint_sweep::fragility::summary(f, rows).trim_end());
            design_lines(&s.design, f.spec.confidence);
        }
        None => {}
    }
    if !s.failed.is_empty() {
        out!("{} jobs failed:", s.failed.len());
        for (case, record, z, t, msg) in &s.failed {
            out!("  {case} / {record} / {}: {msg}", at(*z, *t));
        }
        if let Some(retry) = retry {
            out!(
                "after fixing the cause (raising simulation.max_wall_time or max_steps, say), run the {} failed jobs \
                 again (`--retry-failed`; the finished ones are kept) with:\n{retry}",
                s.failed.len()
            );
        }
    }
    if !s.flagged.is_empty() {
        let counts: Vec<String> = flag_counts(&s.flagged).iter().map(|(n, c)| format!("{n} {c}")).collect();
        out!(
            "{} jobs FLAGGED ({}): they finished outside what the model can stand behind:",
            s.flagged.len(),
            counts.join(", ")
        );
        const SHOWN: usize = 10;
        for (case, record, z, t, _, findings) in s.flagged.iter().take(SHOWN) {
            out!("  {case} / {record} / {}: {findings}", at(*z, *t));
        }
        if s.flagged.len() > SHOWN {
            out!("  ... and {} more (all in the output's /spectrum/with_joint/findings)", s.flagged.len() - SHOWN);
        }
    }
}

/// The fitted curves of a multiple-stripe sweep for `--json`.
fn fragility_json(
    f: &quakejoint_sweep::fragility::StoredFragility,
    rows: &[quakejoint_sweep::fragility::CurveRow],
) -> serde_json::Value {
    json!({
        "measure": f.stripes.measure.label(),
        "units": "g",
        "levels": f.stripes.levels,
        "curves": rows.iter().map(|r| json!({
            "limit_state": r.name, "key": r.key,
            "case": r.at[0], "damping": r.at[1], "period": r.at[2],
            "median": finite(r.median), "beta": finite(r.beta),
            "median_interval": r.median_interval.map(finite), "beta_interval": r.beta_interval.map(finite),
            "annual_frequency": finite(r.annual_frequency),
            "annual_frequency_interval": r.annual_frequency_interval.map(finite),
            "exceeded": r.exceeded, "runs": r.runs, "note": r.note,
        })).collect::<Vec<_>>(),
    })
}

/// A number for JSON: null when not finite.
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// How many flagged jobs carry each flag.
fn flag_counts(flagged: &[(String, String, f64, f64, u32, String)]) -> serde_json::Map<String, serde_json::Value> {
    Flags::ALL
        .iter()
        .map(|(f, name)| (name.to_string(), flagged.iter().filter(|j| Flags(j.4).contains(*f)).count()))
        .filter(|(_, n)| *n > 0)
        .map(|(name, n)| (name, json!(n)))
        .collect()
}

/// `quakejoint merge`.
///
/// `retry`, in a job of `scripts/slurm_array.sh`: the resubmission that runs
/// the failed jobs again.
pub fn merge_summary(s: &quakejoint_sweep::MergeSummary, retry: Option<&str>, json: bool) {
    if json {
        let v = json!({
            "output": s.output.display().to_string(),
            "jobs": s.jobs,
            "finished": s.finished,
            "failed": s.failed,
            "flagged": s.flagged,
            "missing": s.missing,
            "complete": s.missing == 0,
            "notices": s.notices,
            "failed_jobs": s.failed_jobs,
            "flagged_jobs": s.flagged_jobs,
            "fragility": s.fragility.as_ref().map(|(f, rows)| fragility_json(f, rows)),
            "design": s.design.iter().map(design_json).collect::<Vec<_>>(),
        });
        out!("{v}");
        return;
    }
    let state = if s.missing == 0 { "complete" } else { "PARTIAL" };
    const SHOWN: usize = 10;
    let list = |title: String, jobs: &[String]| {
        if !jobs.is_empty() {
            out!("{title}");
            for j in jobs.iter().take(SHOWN) {
                out!("  {j}");
            }
            if jobs.len() > SHOWN {
                out!("  ... and {} more", jobs.len() - SHOWN);
            }
        }
    };
    match retry {
        Some(command) => {
            list(format!("{} jobs failed:", s.failed), &s.failed_jobs);
            out!(
                "after fixing the cause, run them again (on the login node, in the directory slurm_array.sh was run \
                 from: it resubmits their shards) with:\n  {command}"
            );
        }
        None => list(
            format!(
                "{} jobs failed (after fixing the cause, `--retry-failed` on their shards runs them again):",
                s.failed
            ),
            &s.failed_jobs,
        ),
    }
    list(format!("{} jobs FLAGGED (outside what the model can stand behind):", s.flagged), &s.flagged_jobs);
    out!(
        "merged {} of {} jobs ({} failed, {} flagged), {state} -> {}",
        s.finished,
        s.jobs,
        s.failed,
        s.flagged,
        s.output.display()
    );
    if let Some((f, rows)) = &s.fragility {
        out!("{}", quakejoint_sweep::fragility::summary(f, rows).trim_end());
        design_lines(&s.design, f.spec.confidence);
    }
}

/// The jobs whose beams pounded (with the largest contact force) and
/// whose fuses broke.
fn impact_lines(s: &quakejoint_sweep::runner::Summary, at: &dyn Fn(f64, f64) -> String) {
    if let Some((f, case, record, z, t)) = &s.peak_contact {
        out!(
            "pounding: the beams of {} job(s) struck each other; the largest contact force, {:.1} kN, in {case} / \
             {record} / {}",
            s.pounded,
            f / 1e3,
            at(*z, *t)
        );
    }
    if let Some([jobs, broken, exhausted]) = Some(s.fuses).filter(|f| f[0] > 0) {
        out!(
            "fuses: broke in {broken} of the {jobs} finished job(s) with a seismic fuse, their stroke exhausted in \
             {exhausted} (fuse_broken, fuse_stroke_exhausted per job)"
        );
    }
}

/// The choice among the candidates, when the limit states carry targets.
fn design_lines(design: &[quakejoint_sweep::fragility::design::Design], confidence: f64) {
    if design.is_empty() {
        return;
    }
    let label = |[z, t]: [usize; 2]| format!("damping ratio {}, period {} of the sweep", z + 1, t + 1);
    out!("{}", quakejoint_sweep::fragility::design::summary(design, confidence, &label).trim_end());
}

/// The choice among the candidates as JSON.
fn design_json(d: &quakejoint_sweep::fragility::design::Design) -> serde_json::Value {
    json!({
        "damping": d.at[0], "period": d.at[1],
        "targets": d.targets.iter().map(|(key, name, t)| json!({ "key": key, "limit_state": name, "target": t }))
            .collect::<Vec<_>>(),
        "candidates": d.candidates.iter().zip(&d.checks).map(|(c, checks)| json!({
            "case": c.name, "cells": c.cells, "fuse": c.fuse,
            "meets_every_target": checks.iter().all(|k| k.pass),
            "checks": checks.iter().map(|k| json!({
                "annual_frequency": finite(k.frequency), "checked": finite(k.upper), "pass": k.pass, "note": k.note,
            })).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "recommended": d.recommended.map(|c| &d.candidates[c].name),
        "margin": d.recommended.map(|_| json!({ "factor": finite(d.margin.0), "on": d.margin.1 })),
    })
}

/// `quakejoint plan`.
pub fn plan_summary(
    path: &Path,
    plan: &quakejoint_sweep::Plan,
    shards: &[quakejoint_sweep::plan::Estimate],
    threads: usize,
    sbatch: bool,
    json: bool,
) {
    let worst = shards.iter().fold((0.0f64, 0.0f64), |(s, m), e| (s.max(e.seconds), m.max(e.memory_mb)));
    // cluster requests: twice the estimate, rounded up, at least 256 MB and
    // 10 minutes (nodes slower than the reference machine, shared caches)
    let mem_mb = ((2.0 * worst.1 / 64.0).ceil() * 64.0).max(256.0) as u64;
    let minutes = ((3.0 * worst.0 / threads as f64 / 60.0).ceil() + 10.0) as u64;
    let time = format!("{}:{:02}:00", minutes / 60, minutes % 60);
    if sbatch {
        out!("--cpus-per-task={threads} --mem={mem_mb}M --time={time}");
        return;
    }
    let [nc, nr, nz, nt] = plan.dims();
    // a bridge given by its modes sweeps period scales, not periods
    let (axis, one, many) = if plan.modal.is_some() {
        ("period_scales", "period scale", "period scales")
    } else {
        ("periods", "period", "periods")
    };
    if json {
        let v = json!({
            "config": path.display().to_string(),
            "jobs": plan.job_count(),
            "cases": nc, "records": nr, "dampings": nz, axis: nt,
            "threads_per_shard": threads,
            "shards": shards.iter().enumerate().map(|(k, e)| json!({
                "shard": format!("{}/{}", k + 1, shards.len()),
                "jobs": e.jobs,
                "cpu_seconds": e.seconds,
                "memory_mb": e.memory_mb,
            })).collect::<Vec<_>>(),
            "sbatch": {"cpus_per_task": threads, "mem_mb": mem_mb, "time": time},
        });
        out!("{v}");
        return;
    }
    let total: f64 = shards.iter().map(|e| e.seconds).sum();
    let count = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    out!(
        "plan {}: {} ({} x {} x {} x {}), about {} of CPU time on the reference machine",
        path.display(),
        count(plan.job_count(), "job", "jobs"),
        count(nc, "case", "cases"),
        match &plan.stripes {
            // the records are the given ones at every stripe
            Some(s) => format!(
                "{} at {}",
                count(s.ground.len(), "record", "records"),
                count(s.levels.len(), "stripe", "stripes")
            ),
            None => count(nr, "record", "records"),
        },
        count(nz, "damping ratio", "damping ratios"),
        count(nt, one, many),
        quakejoint_sweep::progress::format_duration(total)
    );
    for (k, e) in shards.iter().enumerate() {
        out!(
            "  shard {:>3}/{}: {:>5} jobs, {:>8} on {threads} thread(s), {:.0} MB peak",
            k + 1,
            shards.len(),
            e.jobs,
            quakejoint_sweep::progress::format_duration(e.seconds / threads as f64),
            e.memory_mb
        );
    }
    out!("sbatch resources per shard: --cpus-per-task={threads} --mem={mem_mb}M --time={time}");
    out!(
        "(the estimate is for runs whose joints do not pound; a run whose beams strike each other takes several \
         times as long, its time steps following the impacts: 2.4 times on average for the 180 pounding runs of \
         configs/design.toml, docs/performance.md)"
    );
}

/// `quakejoint compare`.
pub fn compare_summary(a: &Path, b: &Path, diffs: &[String], json: bool) {
    if json {
        out!(
            "{}",
            json!({"a": a.display().to_string(), "b": b.display().to_string(), "identical": diffs.is_empty(), "differences": diffs})
        );
        return;
    }
    if diffs.is_empty() {
        out!(
            "{} and {}: identical results (wall times, creation times and shard labels aside)",
            a.display(),
            b.display()
        );
    } else {
        out!("{} and {} differ:", a.display(), b.display());
        for d in diffs {
            out!("  {d}");
        }
    }
}

/// `quakejoint sweep --check`.
pub fn sweep_check(c: &quakejoint_sweep::runner::Check, retry: bool, json: bool) {
    if json {
        out!(
            "{}",
            json!({
                "output": c.output.display().to_string(),
                "jobs": c.jobs,
                "done": c.done,
                "failed": c.failed,
                "flagged": c.flagged,
                "journal": c.journal,
                "cpu_seconds": c.cpu_seconds,
                "notices": c.notices,
                "output_problem": c.output_problem,
            })
        );
        return;
    }
    for n in c.notices.iter().chain(&c.output_problem) {
        eprintln!("warning: {n}");
    }
    let what = if !c.journal {
        "would start".to_string()
    } else if c.done == c.jobs && c.failed > 0 && retry {
        format!("would run its {} failed jobs again", c.failed)
    } else if c.done == c.jobs && c.failed > 0 {
        format!("is complete, but {} of its jobs failed, which `--retry-failed` runs again", c.failed)
    } else if c.done == c.jobs {
        "is complete".to_string()
    } else {
        format!("would continue: {} of {} jobs done", c.done, c.jobs)
    };
    let fine = if c.output_problem.is_none() {
        "config, records and output are fine"
    } else {
        "config and records are fine, the output is not (above)"
    };
    out!(
        "check {}: {fine}; the sweep {what} ({} jobs, {} failed and {} flagged so far, about {} of CPU time to go)",
        c.output.display(),
        c.jobs,
        c.failed,
        c.flagged,
        quakejoint_sweep::progress::format_duration(c.cpu_seconds)
    );
}
