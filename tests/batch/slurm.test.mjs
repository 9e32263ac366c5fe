// docs/batch/monte-carlo.slurm on a real Slurm: a controller and a node on
// localhost (./cluster.mjs), the study submitted exactly as
// docs/monte-carlo.md says (a 4-task array, then the merge as a job that
// depends on it), and the merged report compared byte for byte with the
// same study run whole in one process.
//
// MONTE_CARLO names the binary (default: target/debug/monte-carlo, built by
// the `batch` layer of `npm test` with the features of the `cargo-test` layer).
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { repo } from '../../scripts/lib.mjs';
import { SlurmCluster } from './cluster.mjs';

const targetDir = process.env.CARGO_TARGET_DIR ?? path.join(repo, 'target');
const binary = process.env.MONTE_CARLO ?? path.join(targetDir, 'debug', 'monte-carlo');
const script = path.join(repo, 'docs', 'batch', 'monte-carlo.slurm');
const scenario = path.join(repo, 'scenarios', 'chattering.json');
const RUNS = '12';
const SEED = '5';
const TASKS = 4;

let cluster;
before(async () => {
  assert.ok(fs.existsSync(binary), `${binary} is missing: cargo build --bin monte-carlo`);
  cluster = await SlurmCluster.start();
});
after(async () => {
  await cluster?.stop();
});

/** Submits with sbatch --parsable; the job id. */
function submit(args, work) {
  const r = cluster.run('sbatch', ['--parsable', `--chdir=${work}`, ...args], { env: { MONTE_CARLO: binary } });
  assert.equal(r.status, 0, `sbatch ${args.join(' ')}: ${r.stderr}`);
  return r.stdout.trim().split(';')[0];
}

test('a 4-task Slurm array merged by a dependent job equals the whole study', async () => {
  const work = path.join(cluster.dir, 'work');
  fs.mkdirSync(work);
  const array = submit([`--array=0-${TASKS - 1}`, script, scenario, RUNS, SEED], work);
  const merge = submit(
    [`--dependency=afterok:${array}`, '--output=merge.log', '--wrap', `"${binary}" merge out/shard-*.jsonl > report.json`],
    work,
  );
  const finished = (states) => states.length > 0 && states.every((s) => !/PENDING|RUNNING|CONFIGURING|COMPLETING/.test(s));
  await cluster.until('end of the merge job', () => finished(cluster.jobState(merge)));

  const arrayStates = cluster.jobState(array);
  assert.equal(arrayStates.length, TASKS, `one state per array task: ${arrayStates}`);
  assert.ok(arrayStates.every((s) => s === 'COMPLETED'), `array tasks: ${arrayStates}\n${cluster.logs()}`);
  assert.deepEqual(cluster.jobState(merge), ['COMPLETED'], fs.readFileSync(path.join(work, 'merge.log'), 'utf8'));

  const shards = fs.readdirSync(path.join(work, 'out')).filter((f) => f.endsWith('.jsonl')).sort();
  assert.deepEqual(shards, ['shard-0.jsonl', 'shard-1.jsonl', 'shard-2.jsonl', 'shard-3.jsonl']);
  // Every task ran its own shard: none is empty, and together they hold every run once.
  const runs = shards.flatMap((f) =>
    fs.readFileSync(path.join(work, 'out', f), 'utf8').trim().split('\n').filter(Boolean).map((l) => JSON.parse(l).run),
  );
  assert.deepEqual([...runs].sort((a, b) => a - b), [...Array(Number(RUNS)).keys()]);

  const whole = spawnSync(binary, ['--scenario', scenario, '--runs', RUNS, '--seed', SEED], { encoding: 'utf8' });
  assert.equal(whole.status, 0, whole.stderr);
  assert.equal(fs.readFileSync(path.join(work, 'report.json'), 'utf8'), whole.stdout);
});
