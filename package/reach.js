// `reachProblems(set)`: the reach benchmark's problem sets as plain data,
// `{ name, scenario, goal: { position, orientation }, goalQ? }[]`, the same
// as Rust's `reach::problems(set)`. Plain JS over the JSON files beside this
// one (problems/<set>.json, written and checked against the Rust sets by
// crate/tests/reach_problem_files.rs): nothing of it is in the wasm module.
// A file holds `base`, the scenario fields every problem of the set shares,
// and per problem the fields of its own (`q0`, `obstacles`, `task`, …).

/** The problem sets, by name. */
export const REACH_SETS = ['pr2', 'panda', 'mbm'];

const isObject = (v) => typeof v === 'object' && v !== null && !Array.isArray(v);

/** `set` checked: one of REACH_SETS, or an Error naming the field. */
function checkSet(set) {
  if (typeof set !== 'string' || !REACH_SETS.includes(set)) {
    const shown = typeof set === 'string' ? `'${set}'` : String(set);
    throw new Error(`set: unknown problem set ${shown} (${REACH_SETS.join(', ')})`);
  }
}

/** The problems of a set file (`data`, parsed) for `set`, each a fresh object. */
function expand(set, data) {
  if (!isObject(data) || data.set !== set || !isObject(data.base) || !Array.isArray(data.problems)) {
    throw new Error(`data: not the '${set}' problem file (problems/${set}.json: { set, base, problems })`);
  }
  return data.problems.map((p, k) => {
    if (!isObject(p) || typeof p.name !== 'string' || !isObject(p.scenario) || !isObject(p.goal)) {
      throw new Error(`data.problems[${k}]: not a problem ({ name, scenario, goal, goalQ? })`);
    }
    const out = {
      name: p.name,
      scenario: structuredClone({ ...data.base, ...p.scenario }),
      goal: structuredClone(p.goal),
    };
    if (p.goalQ !== undefined) out.goalQ = [...p.goalQ];
    return out;
  });
}

/**
 * `reachProblems(set, data?)` over `load(set)`, which returns a set's file
 * parsed (or null where files cannot be read synchronously: a browser, which
 * passes `data`, the file fetched and parsed).
 */
export function makeReachProblems(load) {
  return function reachProblems(set, data) {
    checkSet(set);
    if (data === undefined) {
      data = load ? load(set) : null;
      if (data === null) {
        throw new Error(`data: in a browser, pass the set's file (skeleton-avoidance/problems/${set}.json, fetched and parsed)`);
      }
    }
    return expand(set, data);
  };
}
