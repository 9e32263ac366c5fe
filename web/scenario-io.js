// Scenarios in and out of the page: JSON files and shareable URLs.
//
// A shared URL carries the whole scenario in its fragment,
// `#scenario=<base64url of the UTF-8 JSON>`, so nothing is sent to a server
// and the scene is restored exactly (JSON keeps every double exactly).
// Every failure is an Error whose message a person can read; callers show it
// as text and leave the current scene alone.

const PREFIX = 'scenario=';

/** The fragment (without `#`) that carries `scenario`. */
export function encodeShare(scenario) {
  const bytes = new TextEncoder().encode(JSON.stringify(scenario));
  let binary = '';
  for (const b of bytes) binary += String.fromCharCode(b);
  return PREFIX + btoa(binary).replaceAll('+', '-').replaceAll('/', '_').replace(/=+$/, '');
}

/**
 * The scenario in a URL fragment (`#scenario=…`), or `null` when the
 * fragment carries none. Throws a readable Error when it is malformed.
 */
export function decodeShare(hash) {
  const fragment = hash.startsWith('#') ? hash.slice(1) : hash;
  if (!fragment.startsWith(PREFIX)) return null;
  const data = fragment.slice(PREFIX.length);
  if (!/^[A-Za-z0-9_-]*$/.test(data)) {
    throw new Error('The shared link is damaged: it contains characters a shared scenario never has (was it cut or edited?).');
  }
  let text;
  try {
    const binary = atob(data.replaceAll('-', '+').replaceAll('_', '/'));
    text = new TextDecoder('utf-8', { fatal: true }).decode(Uint8Array.from(binary, (c) => c.charCodeAt(0)));
  } catch {
    throw new Error('The shared link is damaged: its scenario cannot be decoded (was it cut short?).');
  }
  return parseScenarioText(text, 'The shared link');
}

/** Parses scenario JSON text; `source` names where it came from in messages. */
export function parseScenarioText(text, source = 'The file') {
  let value;
  try {
    value = JSON.parse(text);
  } catch (err) {
    throw new Error(`${source} is not valid JSON: ${err.message}`);
  }
  if (value === null || typeof value !== 'object' || Array.isArray(value)) {
    throw new Error(`${source} does not hold a scenario: expected a JSON object with robot, obstacles, dt and duration.`);
  }
  return value;
}

/** Reads a scenario from a `File` (from an `<input type=file>` or a drop). */
export async function readScenarioFile(file) {
  if (file.size > 5_000_000) throw new Error(`${file.name}: too large for a scenario (${file.size} bytes).`);
  return parseScenarioText(await file.text(), `The file "${file.name}"`);
}

/** Offers `scenario` as a JSON file download named `name`. */
export function downloadScenario(scenario, name = 'scenario.json') {
  const blob = new Blob([`${JSON.stringify(scenario, null, 2)}\n`], { type: 'application/json' });
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}
