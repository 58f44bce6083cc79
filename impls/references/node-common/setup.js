'use strict';
// vorobench setup shared by the Node.js references: install the pinned npm packages into the
// cache folder. Run by each manifest (setup = ["node", "../node-common/setup.js", "{cache}"])
// with the manifest's folder as working directory:
//   node ../node-common/setup.js CACHE
// Copies package.json and package-lock.json (exact versions and integrity hashes, transitive
// dependencies included) from the working directory (the manifest's folder, not this one)
// into CACHE and runs `npm ci` there, so node_modules lands in CACHE and never in the
// manifest's folder.
// vorobench re-runs setup when a file of the manifest's folder changes (package.json and
// package-lock.json live there); a change to this file alone does not re-run it.
const fs = require('fs');
const path = require('path');
const { spawnSync } = require('child_process');

const cache = process.argv[2] || process.env.VOROBENCH_CACHE;
if (!cache) {
  process.stderr.write('usage: node ../node-common/setup.js CACHE_DIR (or set VOROBENCH_CACHE), '
    + "run in the manifest's folder\n");
  process.exit(2);
}
const source = process.cwd();
for (const name of ['package.json', 'package-lock.json']) {
  if (!fs.existsSync(path.join(source, name))) {
    process.stderr.write(`setup: no ${name} in ${source} (run setup in the manifest's folder)\n`);
    process.exit(2);
  }
}
fs.mkdirSync(cache, { recursive: true });
for (const name of ['package.json', 'package-lock.json']) {
  fs.copyFileSync(path.join(source, name), path.join(cache, name));
}
const npm = process.platform === 'win32' ? 'npm.cmd' : 'npm';
const args = ['ci', '--prefix', cache, '--omit=dev', '--ignore-scripts', '--no-audit', '--no-fund',
  '--loglevel=error'];
const r = spawnSync(npm, args, { stdio: ['ignore', 'inherit', 'inherit'], shell: process.platform === 'win32' });
if (r.error) {
  process.stderr.write(`setup: cannot run npm: ${r.error.message}\n`);
  process.exit(1);
}
process.exit(r.status === null ? 1 : r.status);
