// `npm start`: installs what is missing, builds the browser package and serves
// the playground on 127.0.0.1, printing the URL to open.
import { ensureTools } from './tools.mjs';
import { buildWasm } from './build.mjs';
import { serve } from './serve.mjs';

if (!ensureTools()) process.exit(1);
if (buildWasm('web') !== 0) {
  console.error('npm start: the wasm build failed (see above).');
  process.exit(1);
}
const port = Number(process.env.PORT ?? 8080);
try {
  const { url } = await serve({ port });
  console.log(`\nPlayground: ${url}  (Ctrl-C to stop)`);
} catch (e) {
  console.error(`npm start: could not listen on 127.0.0.1:${port} (${e.code ?? e.message}); set PORT to another port.`);
  process.exit(1);
}
