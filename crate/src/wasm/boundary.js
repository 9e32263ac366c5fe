// The JavaScript side of the wasm boundary (a wasm-bindgen snippet).
//
// Rust never walks a caller's object itself: a getter or Proxy trap that
// throws while wasm is on the stack unwinds through it, leaks the wasm stack
// and can leave an exported object borrowed for good. Instead every input is
// read here, once, inside try/catch, into plain JSON text that Rust parses.

/** Deepest nesting accepted (a cyclic object ends here). */
const MAX_DEPTH = 64;
/** Longest array accepted anywhere in an input. */
const MAX_ARRAY = 100000;
/** Most values (numbers, strings, …) in one input. */
const MAX_VALUES = 1000000;
/** Longest string accepted. */
const MAX_STRING = 1 << 20;
/** Marks a non-finite number (JSON has none); Rust rewords the error. */
const NON_FINITE = 'non-finite number ';

class Refused extends Error {}

const at = (path, key) => (typeof key === 'number' ? `${path}[${key}]` : path ? `${path}.${key}` : key);
const fail = (path, reason) => {
  throw new Refused(path ? `${path}: ${reason}` : reason);
};

const message = (e) => {
  try {
    return e instanceof Error ? e.message : String(e);
  } catch {
    return 'an exception';
  }
};

/** `encode`, naming `path` when reading the value throws (getter, Proxy trap). */
function encode(value, path, depth, budget) {
  try {
    return encodeValue(value, path, depth, budget);
  } catch (e) {
    if (e instanceof Refused) throw e;
    fail(path, `could not be read (${message(e)})`);
  }
}

function encodeValue(value, path, depth, budget) {
  if (--budget.left < 0) fail(path, `too many values (at most ${MAX_VALUES} in one input)`);
  switch (typeof value) {
    case 'number':
      return Number.isFinite(value) ? JSON.stringify(value) : JSON.stringify(NON_FINITE + String(value));
    case 'string':
      if (value.length > MAX_STRING) fail(path, `string too long (at most ${MAX_STRING} characters)`);
      return JSON.stringify(value);
    case 'boolean':
      return value ? 'true' : 'false';
    case 'undefined':
      return 'null';
    case 'object':
      break;
    default:
      fail(path, `expected JSON-like data, got a ${typeof value}`);
  }
  if (value === null) return 'null';
  if (depth >= MAX_DEPTH) fail(path, `nested too deeply (at most ${MAX_DEPTH} levels; a cyclic object?)`);
  if (ArrayBuffer.isView(value) && !(value instanceof DataView)) {
    if (value.length > MAX_ARRAY) fail(path, `too many elements (at most ${MAX_ARRAY})`);
    const parts = [];
    for (let k = 0; k < value.length; k++) parts.push(encode(Number(value[k]), at(path, k), depth + 1, budget));
    return `[${parts.join(',')}]`;
  }
  if (Array.isArray(value)) {
    const n = value.length;
    if (n > MAX_ARRAY) fail(path, `too many elements (at most ${MAX_ARRAY})`);
    const parts = [];
    for (let k = 0; k < n; k++) {
      let v;
      try {
        v = value[k];
      } catch (e) {
        fail(at(path, k), `could not be read (${message(e)})`);
      }
      parts.push(encode(v, at(path, k), depth + 1, budget));
    }
    return `[${parts.join(',')}]`;
  }
  const keys = Object.keys(value);
  if (keys.length > MAX_ARRAY) fail(path, `too many keys (at most ${MAX_ARRAY})`);
  const parts = [];
  for (const key of keys) {
    let v;
    try {
      v = value[key];
    } catch (e) {
      fail(at(path, key), `could not be read (${message(e)})`);
    }
    if (v === undefined) continue;
    parts.push(`${JSON.stringify(key)}:${encode(v, at(path, key), depth + 1, budget)}`);
  }
  return `{${parts.join(',')}}`;
}

/**
 * `value` as JSON text (non-finite numbers tagged), or throws an `Error`
 * whose message names `field` and the place inside it that could not be read.
 */
export function readJson(value, field) {
  try {
    return encode(value, '', 0, { left: MAX_VALUES });
  } catch (e) {
    if (e instanceof Refused) {
      const msg = e.message;
      throw new Error(field ? (msg.startsWith('[') ? `${field}${msg}` : msg.includes(': ') ? `${field}.${msg}` : `${field}: ${msg}`) : msg);
    }
    throw new Error(`${field || 'input'}: could not be read (${message(e)})`);
  }
}

/** A plain copy of `value` (see `readJson`). */
function snapshot(value, field) {
  if (typeof value !== 'object' || value === null) return value;
  return JSON.parse(readJson(value, field), (_k, v) =>
    typeof v === 'string' && v.startsWith(NON_FINITE) ? Number(v.slice(NON_FINITE.length)) : v,
  );
}

/** The kind of a JS value, for messages (`a string`, `an object`, …). */
const kindOf = (v) => (v === null ? 'null' : Array.isArray(v) ? 'an array' : v === undefined ? 'undefined' : /^[aeiou]/.test(typeof v) ? `an ${typeof v}` : `a ${typeof v}`);

/**
 * Checks or reads one argument as `spec` says: `name` (plain data, read
 * once), `name:number` (a finite JS number, no coercion), `name:number?`
 * (the same, or undefined / null), `name:World` (a live `World`, passed
 * as it is).
 */
function argument(value, spec) {
  const [name, kind] = spec.split(':');
  switch (kind) {
    case undefined:
      return snapshot(value, name);
    case 'number?':
      if (value === undefined || value === null) return undefined;
    // falls through
    case 'number':
      if (typeof value !== 'number') throw new Error(`${name}: expected a number, got ${kindOf(value)}`);
      if (!Number.isFinite(value)) throw new Error(`${name}: not a finite number`);
      return value;
    case 'World':
      if (value === null || typeof value !== 'object' || !('__wbg_ptr' in value)) {
        throw new Error(`${name}: expected a World, got ${kindOf(value)}`);
      }
      if (!value.__wbg_ptr) throw new Error(`${name}: this World has been freed`);
      return value;
    default:
      return value;
  }
}

/**
 * Guards the methods of an exported class, given one instance: each
 * argument is checked (numbers) or read into plain data (objects) before
 * wasm borrows the object (so a getter that throws, or calls back into the
 * object, cannot leave it borrowed), and a freed object throws
 * `Error: this <name> has been freed` instead of trapping; a second
 * `free()` does nothing. `argNames` maps a method to its argument specs
 * (see `argument`).
 */
export function guardClass(instance, name, argNames) {
  const proto = Object.getPrototypeOf(instance);
  if (proto.__guarded) return;
  const freed = () => new Error(`this ${name} has been freed`);
  for (const key of Object.getOwnPropertyNames(proto)) {
    if (key === 'constructor' || key.startsWith('__')) continue;
    const desc = Object.getOwnPropertyDescriptor(proto, key);
    if (typeof desc.get === 'function') {
      const get = desc.get;
      Object.defineProperty(proto, key, {
        ...desc,
        get() {
          if (!this.__wbg_ptr) throw freed();
          return get.call(this);
        },
      });
    } else if (typeof desc.value === 'function') {
      const method = desc.value;
      const names = argNames[key] || [];
      const guarded =
        key === 'free'
          ? function free() {
              if (this.__wbg_ptr) method.call(this);
            }
          : function (...args) {
              if (!this.__wbg_ptr) throw freed();
              // Arguments past the method's own are ignored, never read.
              const n = Math.max(names.length, method.length);
              const plain = Array.from({ length: n }, (_, i) => argument(args[i], names[i] || `argument ${i + 1}`));
              if (!this.__wbg_ptr) throw freed();
              return method.apply(this, plain);
            };
      Object.defineProperty(proto, key, { ...desc, value: guarded });
    }
  }
  // `using` calls [Symbol.dispose]: the guarded free, so that disposing a
  // freed object does nothing (wasm-bindgen's own alias is the raw free).
  if (typeof Symbol.dispose === 'symbol') {
    Object.defineProperty(proto, Symbol.dispose, { value: proto.free, writable: true, configurable: true });
  }
  Object.defineProperty(proto, '__guarded', { value: true });
}

/**
 * Reads the options of `robotFromUrdf` / `fitUrdf` / `Viewer.setUrdf` once:
 * `{ json, meshes }`, the options without `meshes` as JSON text, and the
 * mesh files as a fresh plain object of fresh `Uint8Array` copies (so Rust
 * never touches the caller's objects). Throws an Error naming the field.
 */
export function readUrdfOptions(options, maxBytes) {
  if (options === undefined || options === null) return { json: 'null', meshes: undefined };
  if (typeof options !== 'object') fail('options', `expected an object, got ${kindOf(options)}`);
  let keys;
  try {
    keys = Object.keys(options);
  } catch (e) {
    fail('options', `could not be read (${message(e)})`);
  }
  const rest = {};
  let meshes;
  for (const k of keys) {
    let v;
    try {
      v = options[k];
    } catch (e) {
      fail(at('options', k), `could not be read (${message(e)})`);
    }
    if (k === 'meshes') meshes = v;
    else rest[k] = v;
  }
  const json = readJson(rest, 'options');
  if (meshes === undefined || meshes === null) return { json, meshes: undefined };
  let list = false;
  try {
    list = Array.isArray(meshes);
  } catch (e) {
    fail('options.meshes', `could not be read (${message(e)})`);
  }
  if (typeof meshes !== 'object' || list) fail('options.meshes', 'expected an object mapping paths to Uint8Array or ArrayBuffer');
  let names;
  try {
    names = Object.keys(meshes);
  } catch (e) {
    fail('options.meshes', `could not be read (${message(e)})`);
  }
  const out = {};
  for (const name of names) {
    let bytes = null;
    try {
      const v = meshes[name];
      if (v instanceof Uint8Array) bytes = v;
      else if (v instanceof ArrayBuffer) bytes = new Uint8Array(v);
    } catch (e) {
      fail('options.meshes', `"${name}" could not be read (${message(e)})`);
    }
    if (!bytes) fail('options.meshes', `"${name}" is not a Uint8Array or an ArrayBuffer`);
    if (bytes.length > maxBytes) fail('options.meshes', `"${name}" has ${bytes.length} bytes, more than the ${maxBytes} a mesh may have`);
    out[name] = bytes.slice();
  }
  return { json, meshes: out };
}
