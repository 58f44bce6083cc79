'use strict';
// vorobench setup: install the pinned npm packages into the cache folder.
//   node setup.js CACHE
// Copies package.json and package-lock.json (exact versions and integrity hashes, transitive
// dependencies included) from this folder into CACHE and runs `npm ci` there, so
// node_modules lands in CACHE and never in the manifest's folder.
const fs = require('fs');
const path = require('path');
const { spawnSync } = require('child_process');

const cache = process.argv[2] || process.env.VOROBENCH_CACHE;
if (!cache) {
  process.stderr.write('usage: node setup.js CACHE_DIR (or set VOROBENCH_CACHE)\n');
  process.exit(2);
}
fs.mkdirSync(cache, { recursive: true });
for (const name of ['package.json', 'package-lock.json']) {
  fs.copyFileSync(path.join(__dirname, name), path.join(cache, name));
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
