//! `relnav` — the evaluation engine's command line.
//!
//! * `relnav reproduce [--paper 000|001|002|003|eccentric|sensors|all] [--runs M] [--out DIR]` runs
//!   the papers' numerical examples and the eccentric-orbit and multi-sensor scenarios (built-in scenario files) and prints, per scenario, a Markdown
//!   table of the paper's published figures beside ours; writes CSV time series and PNG
//!   plots under `DIR/<scenario>/`. Paper 001 also runs its Mars approach
//!   ([`relnav_eval::mars`]): Tables 3-5 beside the paper's, in `DIR/paper001_mars/tables.md`.
//! * `relnav simulate SCENARIO.toml [--runs M] [--out DIR]` does the same for any file.
//! * `relnav scenarios [--show NAME]` lists (or prints) the built-in scenarios.
//!
//! Ctrl-C stops a campaign after the runs in progress; what finished is reported and
//! marked as interrupted.

use clap::{Parser, Subcommand};
use relnav_eval::{builtin, mars, metrics, report, runner, scenario::Scenario};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[derive(Parser)]
#[command(
    name = "relnav",
    version,
    about = "Relative-navigation evaluation engine: Monte Carlo campaigns, metrics against the PCRLB, reproduction of the papers"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Reproduce the papers' numerical examples.
    Reproduce {
        /// Which paper: 000, 001, 002, 003, eccentric (the eccentric-orbit scenarios), sensors (the multi-sensor ones) or all.
        #[arg(long, default_value = "all", value_parser = ["000", "001", "002", "003", "eccentric", "sensors", "all"])]
        paper: String,
        /// Monte Carlo runs per scenario (default: the scenario's own count).
        #[arg(long)]
        runs: Option<u32>,
        /// Output directory for CSV and PNG files.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Worker threads (default: one per core; results do not depend on it).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Skip the PNG plots.
        #[arg(long)]
        no_plots: bool,
    },
    /// Run any scenario file.
    Simulate {
        /// The scenario (TOML).
        scenario: PathBuf,
        /// Monte Carlo runs (default: the scenario's own count).
        #[arg(long)]
        runs: Option<u32>,
        /// Output directory for CSV and PNG files.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Worker threads (default: one per core; results do not depend on it).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Skip the PNG plots.
        #[arg(long)]
        no_plots: bool,
    },
    /// List the built-in scenarios, or print one.
    Scenarios {
        /// Print this scenario's TOML.
        #[arg(long)]
        show: Option<String>,
    },
}

fn campaign(
    s: &Scenario,
    runs: Option<u32>,
    out: &Path,
    threads: usize,
    plots: bool,
    cancel: &Arc<AtomicBool>,
) -> Result<(), String> {
    let opts = runner::Options {
        runs,
        threads,
        progress: true,
        cancel: Some(cancel.clone()),
    };
    let t0 = std::time::Instant::now();
    let r = runner::run(s, &opts)?;
    let secs = t0.elapsed().as_secs_f64();
    // campaign throughput (scripts/bench.sh collects these lines): the
    // Monte Carlo runs alone, without the metrics, CSV and plots written below
    eprintln!(
        "throughput {}: {} runs of {} steps, {} filters in {secs:.3} s = {:.2} runs/s",
        s.name,
        r.runs,
        r.t.len(),
        r.filters.len(),
        f64::from(r.runs) / secs
    );
    let summary = metrics::summarize(&r);
    println!("{}", report::markdown_table(&r, &summary));
    let dir = out.join(&s.name);
    std::fs::create_dir_all(&dir).map_err(|e| format!("create {}: {e}", dir.display()))?;
    let mut files = report::write_csv(&r, &summary, &dir)?;
    if plots {
        files.extend(report::write_plots(&r, &dir)?);
    }
    let names: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
    println!("wrote: {}\n", names.join(", "));
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let c = cancel.clone();
        // a second Ctrl-C while stopping falls back to the default (kill)
        let _ = ctrlc::set_handler(move || {
            if c.swap(true, Ordering::Relaxed) {
                std::process::exit(130);
            }
            eprintln!("\ninterrupted: finishing the runs in progress (Ctrl-C again to abort)");
        });
    }
    let result = match cli.command {
        Command::Reproduce {
            paper,
            runs,
            out,
            threads,
            no_plots,
        } => {
            let mut r = Ok(());
            let mars: Vec<_> = builtin::MARS
                .iter()
                .filter(|(p, _, _)| paper == "all" || *p == paper)
                .collect();
            for (_, name, text) in mars {
                if cancel.load(Ordering::Relaxed) {
                    break;
                }
                r = builtin::parse_mars(text)
                    .map_err(|e| format!("built-in scenario {name}: {e}"))
                    .and_then(|s| {
                        let table = mars::reproduce(&s, runs)?;
                        println!("{table}");
                        let dir = out.join(&s.name);
                        std::fs::create_dir_all(&dir)
                            .and_then(|()| std::fs::write(dir.join("tables.md"), &table))
                            .map_err(|e| format!("write {}: {e}", dir.display()))?;
                        println!("wrote: {}\n", dir.join("tables.md").display());
                        Ok(())
                    });
                if r.is_err() {
                    break;
                }
            }
            for (name, text) in builtin::for_paper(&paper) {
                if r.is_err() {
                    break;
                }
                if cancel.load(Ordering::Relaxed) {
                    break;
                }
                r = Scenario::from_toml(text)
                    .map_err(|e| format!("built-in scenario {name}: {e}"))
                    .and_then(|s| campaign(&s, runs, &out, threads, !no_plots, &cancel));
                if r.is_err() {
                    break;
                }
            }
            r
        }
        Command::Simulate {
            scenario,
            runs,
            out,
            threads,
            no_plots,
        } => std::fs::read_to_string(&scenario)
            .map_err(|e| format!("{}: {e}", scenario.display()))
            .and_then(|t| {
                Scenario::from_toml(&t).map_err(|e| format!("{}: {e}", scenario.display()))
            })
            .and_then(|s| campaign(&s, runs, &out, threads, !no_plots, &cancel)),
        Command::Scenarios { show } => match show {
            Some(n) => builtin::BUILTIN
                .iter()
                .chain(builtin::MARS)
                .find(|(_, name, _)| *name == n)
                .map(|(_, _, t)| print!("{t}"))
                .ok_or_else(|| format!("no built-in scenario named {n}")),
            None => {
                for (p, n, t) in builtin::BUILTIN {
                    let title = Scenario::from_toml(t).map(|s| s.title).unwrap_or_default();
                    println!("{p}  {n:<24} {title}");
                }
                for (p, n, t) in builtin::MARS {
                    let title = builtin::parse_mars(t).map(|s| s.title).unwrap_or_default();
                    println!("{p}  {n:<24} {title}");
                }
                Ok(())
            }
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("relnav: {e}");
            ExitCode::FAILURE
        }
    }
}
