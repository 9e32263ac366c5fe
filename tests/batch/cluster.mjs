// A throwaway Slurm cluster on localhost for the batch test: one controller
// (slurmctld) and one compute node (slurmd) with their own configuration,
// state, spool and logs in a temporary directory, on free ports, with no
// authentication daemon (auth/none, cred/none: the cluster only listens to
// this machine and lives for one test). Both daemons run in the foreground
// as children of the test and are killed by `stop()`.
//
// Nothing here waits for a time: every wait polls a state (the node idle, a
// job finished) and gives up only after a generous ceiling, with the
// daemons' logs in the error, so a busy machine makes the test slower,
// never wrong.
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { commandPath } from '../../scripts/tools.mjs';

/** How long a state may take to arrive before the test gives up, ms. */
const CEILING_MS = 300_000;
/** Between two looks at a state, ms. */
const POLL_MS = 250;

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** A TCP port no one listens on now. */
async function freePort() {
  return new Promise((resolve, reject) => {
    const server = net.createServer();
    server.once('error', reject);
    server.listen(0, '127.0.0.1', () => {
      const { port } = server.address();
      server.close(() => resolve(port));
    });
  });
}

function config({ dir, host, node, user, ctldPort, dPort, cpus }) {
  return [
    'ClusterName=skeleton-batch-test',
    // slurmctld runs only where the host's own name is the controller's.
    `SlurmctldHost=${host}(127.0.0.1)`,
    `SlurmctldPort=${ctldPort}`,
    `SlurmdPort=${dPort}`,
    'AuthType=auth/none',
    'CredType=cred/none',
    `SlurmUser=${user}`,
    `SlurmdUser=${user}`,
    `StateSaveLocation=${dir}/state`,
    `SlurmdSpoolDir=${dir}/spool`,
    `SlurmctldPidFile=${dir}/slurmctld.pid`,
    `SlurmdPidFile=${dir}/slurmd.pid`,
    `SlurmctldLogFile=${dir}/slurmctld.log`,
    `SlurmdLogFile=${dir}/slurmd.log`,
    'ProctrackType=proctrack/linuxproc',
    'TaskPlugin=task/none',
    'SelectType=select/cons_tres',
    'SelectTypeParameters=CR_Core',
    'SchedulerType=sched/backfill',
    // A job whose dependency can never be met is cancelled, not left pending.
    'SchedulerParameters=kill_invalid_depend',
    'ReturnToService=2',
    'JobCompType=jobcomp/none',
    'AccountingStorageType=accounting_storage/none',
    'MpiDefault=none',
    // Finished jobs stay visible to scontrol for this long (s): the test reads their state.
    'MinJobAge=3600',
    `NodeName=${node} NodeAddr=127.0.0.1 CPUs=${cpus} State=UNKNOWN`,
    `PartitionName=test Nodes=${node} Default=YES MaxTime=INFINITE State=UP`,
    '',
  ].join('\n');
}

export class SlurmCluster {
  /** Writes the configuration and starts both daemons; resolves once the node is idle. */
  static async start() {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'sa-slurm-'));
    fs.mkdirSync(path.join(dir, 'state'));
    fs.mkdirSync(path.join(dir, 'spool'));
    const node = 'satest';
    const settings = {
      dir,
      node,
      host: os.hostname().split('.')[0],
      user: os.userInfo().username,
      ctldPort: await freePort(),
      dPort: await freePort(),
      cpus: Math.max(1, Math.min(4, os.availableParallelism?.() ?? os.cpus().length)),
    };
    const conf = path.join(dir, 'slurm.conf');
    fs.writeFileSync(conf, config(settings));
    const cluster = new SlurmCluster(dir, conf, node);
    cluster.#daemon('slurmctld', ['-D', '-i', '-f', conf]);
    cluster.#daemon('slurmd', ['-D', '-N', node, '-f', conf]);
    await cluster.until('the node to be idle', () => /idle/.test(cluster.run('sinfo', ['-h', '-n', node, '-o', '%T']).stdout));
    return cluster;
  }

  #children = [];

  constructor(dir, conf, node) {
    this.dir = dir;
    this.conf = conf;
    this.node = node;
    this.env = { ...process.env, SLURM_CONF: conf };
  }

  #daemon(name, args) {
    const bin = commandPath(name);
    if (bin === null) throw new Error(`${name} is not installed (node scripts/tools.mjs --slurm)`);
    const child = spawn(bin, args, { env: this.env, stdio: ['ignore', 'ignore', 'pipe'] });
    child.stderr.on('data', () => {});
    this.#children.push(child);
  }

  /** Runs a Slurm client command against this cluster; `{ status, stdout, stderr }`. */
  run(cmd, args, { cwd = this.dir, env = {} } = {}) {
    const r = spawnSync(commandPath(cmd) ?? cmd, args, { cwd, encoding: 'utf8', env: { ...this.env, ...env } });
    return { status: r.status ?? 1, stdout: r.stdout ?? '', stderr: r.stderr ?? String(r.error ?? '') };
  }

  /** The state of a job (`COMPLETED`, `PENDING`, …) as the controller reports it. */
  jobState(id) {
    const out = this.run('scontrol', ['show', 'job', '-o', String(id)]).stdout;
    return [...out.matchAll(/JobState=(\S+)/g)].map((m) => m[1]);
  }

  /** Polls `ready()` until it is true; throws with the daemons' logs past the ceiling. */
  async until(what, ready) {
    const t0 = Date.now();
    while (!ready()) {
      const died = this.#children.find((c) => c.exitCode !== null || c.signalCode !== null);
      if (died) throw new Error(`Slurm: ${died.spawnfile} exited (${died.exitCode ?? died.signalCode}) while waiting for ${what}\n${this.logs()}`);
      if (Date.now() - t0 > CEILING_MS) throw new Error(`Slurm: no ${what} after ${CEILING_MS / 1000} s\n${this.logs()}`);
      await sleep(POLL_MS);
    }
  }

  /** The tail of both daemons' logs, for a failure message. */
  logs() {
    return ['slurmctld.log', 'slurmd.log']
      .map((f) => {
        const file = path.join(this.dir, f);
        const text = fs.existsSync(file) ? fs.readFileSync(file, 'utf8') : '(none)';
        return `--- ${f}\n${text.split('\n').slice(-25).join('\n')}`;
      })
      .join('\n');
  }

  /** Kills both daemons and waits for them to exit; removes the directory. */
  async stop() {
    await Promise.all(
      this.#children.map(
        (child) =>
          new Promise((resolve) => {
            if (child.exitCode !== null || child.signalCode !== null) return resolve();
            child.once('exit', resolve);
            child.kill('SIGTERM');
          }),
      ),
    );
    fs.rmSync(this.dir, { recursive: true, force: true });
  }
}
