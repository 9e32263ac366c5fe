//! `monte-carlo`: Monte Carlo studies of a scenario from the command line,
//! whole or in shards for a batch scheduler (`docs/monte-carlo.md`).
//!
//! ```text
//! monte-carlo --scenario FILE|--example NAME --runs N [--seed S] [--shard i/n]
//! monte-carlo merge [--rows] [FILE …]
//! ```
//!
//! Without `--shard` it prints the study's report (JSON). With
//! `--shard i/n` it prints one JSON line per run of shard `i` (a contiguous
//! block of runs, see `study::Shard`); `merge` reads such lines from the
//! files (or stdin when none, or `-`) and prints the report, the same as
//! the whole study run at once. Built with `--features parallel`, the runs
//! of one process are spread over every core.

use std::io::{BufRead, Write};
use std::process::ExitCode;

use skeleton_avoidance::scenario::{self, Scenario};
use skeleton_avoidance::study::{self, MonteCarloOptions, RunRow, Shard};

const USAGE: &str = "usage:
  monte-carlo (--scenario FILE | --example NAME) --runs N [--seed S] [--shard i/n] [--rows]
      the report of the study (JSON), or with --shard i/n one JSON line per run
      of shard i of n (shards are numbered from 0; shard i holds runs
      floor(i*N/n) .. floor((i+1)*N/n) - 1)
  monte-carlo merge [--rows] [FILE ...]
      the report of JSON lines read from the files (stdin when none, or -)";

struct Study {
    scenario: Scenario,
    options: MonteCarloOptions,
    shard: Option<Shard>,
}

fn value<'a>(
    args: &mut impl Iterator<Item = &'a String>,
    flag: &str,
) -> Result<&'a String, String> {
    args.next()
        .ok_or_else(|| format!("{flag}: expects a value"))
}

fn number(flag: &str, text: &str) -> Result<u64, String> {
    text.parse::<u64>()
        .map_err(|_| format!("{flag}: expected a whole number ≥ 0, got \"{text}\""))
}

fn parse_study(args: &[String]) -> Result<Study, String> {
    let (mut scenario, mut runs, mut seed, mut shard, mut rows) = (None, None, 0, None, false);
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        match flag.as_str() {
            "--scenario" => {
                let path = value(&mut it, flag)?;
                let text = std::fs::read_to_string(path)
                    .map_err(|e| format!("--scenario: cannot read {path}: {e}"))?;
                let s = Scenario::from_json(&text).map_err(|e| format!("{path}: {e}"))?;
                scenario = Some(s);
            }
            "--example" => {
                let name = value(&mut it, flag)?;
                scenario = Some(scenario::example(name).map_err(|e| format!("--example: {e}"))?);
            }
            "--runs" => runs = Some(number(flag, value(&mut it, flag)?)?),
            "--seed" => seed = number(flag, value(&mut it, flag)?)?,
            "--shard" => {
                let s = Shard::parse(value(&mut it, flag)?).map_err(|e| format!("--{e}"))?;
                shard = Some(s);
            }
            "--rows" => rows = true,
            other => return Err(format!("unknown argument \"{other}\"")),
        }
    }
    let scenario = scenario.ok_or("--scenario FILE or --example NAME is required")?;
    let runs = runs.ok_or("--runs N is required")?;
    study::check_runs("runs", runs).map_err(|e| format!("--{e}"))?;
    Ok(Study {
        scenario,
        options: MonteCarloOptions { runs, seed, rows },
        shard,
    })
}

fn run_study(study: &Study, out: &mut impl Write) -> Result<(), String> {
    let Some(shard) = study.shard else {
        let report =
            study::monte_carlo(&study.scenario, &study.options).map_err(|e| e.to_string())?;
        let json = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        return writeln!(out, "{json}").map_err(|e| e.to_string());
    };
    let range = shard.range(study.options.runs);
    if range.is_empty() {
        return Ok(());
    }
    let (seed, scenario) = (study.options.seed, &study.scenario);
    let rows = study::monte_carlo_runs(scenario, seed, range.start, range.end - range.start)
        .map_err(|e| e.to_string())?;
    for row in rows {
        let line = serde_json::to_string(&row).map_err(|e| e.to_string())?;
        writeln!(out, "{line}").map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn read_rows(source: &str, reader: impl BufRead, rows: &mut Vec<RunRow>) -> Result<(), String> {
    for (n, line) in reader.lines().enumerate() {
        let line = line.map_err(|e| format!("{source}: {e}"))?;
        if line.trim().is_empty() {
            continue;
        }
        let row: RunRow =
            serde_json::from_str(&line).map_err(|e| format!("{source}:{}: {e}", n + 1))?;
        rows.push(row);
    }
    Ok(())
}

fn merge(args: &[String], out: &mut impl Write) -> Result<(), String> {
    let keep = args.iter().any(|a| a == "--rows");
    let files: Vec<&String> = args.iter().filter(|a| *a != "--rows").collect();
    if let Some(bad) = files.iter().find(|f| f.starts_with("--")) {
        return Err(format!("unknown argument \"{bad}\""));
    }
    let mut rows = Vec::new();
    if files.is_empty() {
        read_rows("stdin", std::io::stdin().lock(), &mut rows)?;
    }
    for f in files {
        if f == "-" {
            read_rows("stdin", std::io::stdin().lock(), &mut rows)?;
        } else {
            let file = std::fs::File::open(f).map_err(|e| format!("{f}: {e}"))?;
            read_rows(f, std::io::BufReader::new(file), &mut rows)?;
        }
    }
    let report = study::merge(rows, keep).map_err(|e| e.to_string())?;
    let json = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    writeln!(out, "{json}").map_err(|e| e.to_string())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let result = match args.first().map(String::as_str) {
        None | Some("-h" | "--help") => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Some("merge") => merge(&args[1..], &mut out),
        Some(_) => parse_study(&args).and_then(|s| run_study(&s, &mut out)),
    };
    let flushed = out.flush().map_err(|e| e.to_string());
    match result.and(flushed) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("monte-carlo: {e}\n\n{USAGE}");
            ExitCode::from(2)
        }
    }
}
