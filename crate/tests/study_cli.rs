//! The `monte-carlo` command line (native only): shards written as JSON
//! lines and merged give the report of the whole study, byte for byte; a
//! shard outside `0..n` and bad arguments are refused with a message.

#![cfg(not(target_arch = "wasm32"))]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn cli(args: &[&str], stdin: Option<&str>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_monte-carlo"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let input = stdin.unwrap_or("").to_owned();
    let mut pipe = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || pipe.write_all(input.as_bytes()));
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    out
}

fn text(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).unwrap()
}

const STUDY: &[&str] = &["--example", "chattering", "--runs", "7", "--seed", "11"];

#[test]
fn shards_merged_from_files_and_stdin_give_the_whole_study() {
    let whole = cli(STUDY, None);
    assert!(
        whole.status.success(),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    let dir = std::env::temp_dir().join(format!("sa-monte-carlo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    let mut all_lines = String::new();
    for i in 0..3 {
        let shard = format!("{i}/3");
        let out = cli(&[STUDY, &["--shard", &shard]].concat(), None);
        assert!(out.status.success());
        let lines = text(&out);
        // shard i of 7 runs over 3: runs ⌊7i/3⌋ .. ⌊7(i+1)/3⌋
        assert_eq!(lines.lines().count(), [2, 2, 3][i]);
        let path = dir.join(format!("shard-{i}.jsonl"));
        std::fs::write(&path, &lines).unwrap();
        files.push(path.to_string_lossy().into_owned());
        all_lines = lines + &all_lines;
    }
    let merged = cli(&["merge", &files[2], &files[0], &files[1]], None);
    assert!(
        merged.status.success(),
        "{}",
        String::from_utf8_lossy(&merged.stderr)
    );
    assert_eq!(text(&merged), text(&whole));
    let piped = cli(&["merge"], Some(&all_lines));
    assert_eq!(text(&piped), text(&whole));
    // a missing shard is noticed
    let partial = cli(&["merge", &files[0], &files[2]], None);
    assert!(!partial.status.success());
    assert!(String::from_utf8_lossy(&partial.stderr).contains("missing"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_shard_outside_its_range_and_bad_arguments_are_refused() {
    let cases: [(&[&str], &str); 7] = [
        (&["--shard", "3/3"], "shard: 3 is outside 0..3"),
        (&["--shard", "0/0"], "number of shards must be ≥ 1"),
        (&["--shard", "one/3"], "expected i/n"),
        (&["--runs", "0"], "--runs: must be ≥ 1"),
        (&["--runs", "2000000"], "--runs: at most 1000000"),
        (&["--seed", "NaN"], "--seed: expected a whole number"),
        (&["--wat"], "unknown argument"),
    ];
    for (extra, message) in cases {
        let args = [&["--example", "chattering", "--runs", "2"], extra].concat();
        let out = cli(&args, None);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        assert!(err.contains(message), "{extra:?}: {err}");
        assert!(out.stdout.is_empty());
    }
    let out = cli(&["merge"], Some("{\"run\": 0}\n"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("stdin:1"));
}

#[test]
fn the_slurm_recipe_shards_and_merges_into_the_whole_study() {
    // docs/batch/monte-carlo.slurm run as four array tasks would run it.
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../docs/batch/monte-carlo.slurm"
    );
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/chattering.json");
    let dir = std::env::temp_dir().join(format!("sa-slurm-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for task in 0..4 {
        let status = Command::new("bash")
            .args([script, scenario, "6", "3"])
            .current_dir(&dir)
            .env("MONTE_CARLO", env!("CARGO_BIN_EXE_monte-carlo"))
            .env("SLURM_ARRAY_TASK_ID", task.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "4")
            .status()
            .unwrap();
        assert!(status.success());
    }
    let shards: Vec<String> = (0..4)
        .map(|k| {
            dir.join(format!("out/shard-{k}.jsonl"))
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    let refs: Vec<&str> = std::iter::once("merge")
        .chain(shards.iter().map(String::as_str))
        .collect();
    let merged = cli(&refs, None);
    let whole = cli(
        &["--scenario", scenario, "--runs", "6", "--seed", "3"],
        None,
    );
    assert!(merged.status.success() && whole.status.success());
    assert_eq!(text(&merged), text(&whole));
    std::fs::remove_dir_all(&dir).unwrap();
}
