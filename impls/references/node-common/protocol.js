'use strict';
// What the Node.js reference programs (../delaunator/triangulate.js, ../d3-delaunay/voronoi.js)
// share of vorobench's executable protocol (docs/executables.md): the command line, reading
// and parsing the text input, loading the npm package that setup installed, buffered output
// and the error wrapper. Each program keeps only its own library calls and output.
//
// This folder is no implementation (it has no impl.toml); the programs load this file with
//   require(path.join(__dirname, '..', 'node-common', 'protocol.js'))
// and their manifests run ../node-common/setup.js as their setup.

const fs = require('fs');
const path = require('path');
const { createRequire } = require('module');
const { pathToFileURL } = require('url');

// The version of `packageName` pinned in the package.json of folder `dir` (the program's own
// folder: needs no setup).
function pinnedVersion(dir, packageName) {
  const pkg = JSON.parse(fs.readFileSync(path.join(dir, 'package.json'), 'utf8'));
  return pkg.dependencies[packageName];
}

// The module of `packageName` as setup installed it in CACHE/node_modules: resolved from
// CACHE, then loaded with a dynamic import() of the resolved file, so an ES module package
// loads from this CommonJS code as well as a CommonJS one would.
async function loadModule(cache, packageName) {
  const req = createRequire(path.join(path.resolve(cache), 'vorobench-resolve.js'));
  const entry = req.resolve(packageName);
  return import(pathToFileURL(entry).href);
}

async function readStdin() {
  const chunks = [];
  for await (const chunk of process.stdin) chunks.push(chunk);
  return Buffer.concat(chunks).toString('latin1');
}

// Parse `n [weighted]` then n lines `x y`; numbers are Python repr strings, which Number()
// converts exactly (correctly rounded, hence round-trip exact). `packageName` names the
// library in the error for weighted input (neither program takes weights).
function parseInput(text, packageName) {
  const len = text.length;
  let pos = 0;
  const lineEnd = text.indexOf('\n');
  const header = (lineEnd < 0 ? text : text.slice(0, lineEnd)).trim().split(/\s+/);
  if (header.length === 0 || header[0] === '') throw new Error('empty input');
  const n = Number(header[0]);
  if (!Number.isInteger(n) || n < 0) throw new Error(`bad site count: ${header[0]}`);
  if (header.length > 1) {
    if (header[1] === 'weighted') throw new Error(`weighted sites are not supported by ${packageName}`);
    throw new Error(`unexpected header: ${header.join(' ')}`);
  }
  pos = lineEnd < 0 ? len : lineEnd + 1;
  const coords = new Float64Array(2 * n);
  const want = 2 * n;
  for (let k = 0; k < want; k++) {
    while (pos < len && text.charCodeAt(pos) <= 32) pos++;
    const start = pos;
    while (pos < len && text.charCodeAt(pos) > 32) pos++;
    if (start === pos) throw new Error(`expected ${want} coordinates, got ${k}`);
    const v = Number(text.slice(start, pos));
    if (!Number.isFinite(v)) throw new Error(`bad coordinate: ${text.slice(start, pos)}`);
    coords[k] = v;
  }
  return { n, coords };
}

// Writes ASCII output into one growing Buffer, integers digit by digit.
class Output {
  constructor(capacity) {
    this.buf = Buffer.allocUnsafe(Math.max(capacity, 256));
    this.len = 0;
  }
  ensure(extra) {
    if (this.len + extra <= this.buf.length) return;
    const bigger = Buffer.allocUnsafe(Math.max(2 * this.buf.length, this.len + extra));
    this.buf.copy(bigger, 0, 0, this.len);
    this.buf = bigger;
  }
  int(v) { // needs ensure(12) beforehand
    const buf = this.buf;
    if (v < 0) {
      buf[this.len++] = 45; // '-'
      v = -v;
    }
    let digits = 1;
    for (let p = 10; p <= v; p *= 10) digits++;
    let end = this.len + digits;
    this.len = end;
    do {
      buf[--end] = 48 + (v % 10);
      v = Math.floor(v / 10);
    } while (v > 0);
  }
  byte(c) {
    this.buf[this.len++] = c;
  }
  text(s) {
    this.ensure(s.length);
    this.len += this.buf.write(s, this.len, 'latin1');
  }
  flush() {
    process.stdout.write(this.buf.subarray(0, this.len));
  }
}

// The whole program around its own part `body`, for the script `scriptFile` (the caller's
// __filename) built on the npm package `packageName`:
//   node SCRIPT --version  prints the version pinned in the script folder's package.json;
//   node SCRIPT CACHE      (or VOROBENCH_CACHE set) loads the package from CACHE, reads and
//                          parses stdin, then awaits body(lib, { n, coords }) with lib the
//                          package's module namespace.
// Any error goes to stderr as `packageName: stack` with exit status 1.
function runProgram(packageName, scriptFile, body) {
  async function main() {
    const args = process.argv.slice(2);
    if (args[0] === '--version') {
      process.stdout.write(pinnedVersion(path.dirname(scriptFile), packageName) + '\n');
      return;
    }
    const cache = args[0] || process.env.VOROBENCH_CACHE;
    if (!cache) throw new Error(`usage: node ${path.basename(scriptFile)} CACHE_DIR < input`);
    const lib = await loadModule(cache, packageName);

    const input = parseInput(await readStdin(), packageName);

    await body(lib, input);
  }

  main().catch((err) => {
    process.stderr.write(`${packageName}: ${err && err.stack ? err.stack : err}\n`);
    process.exitCode = 1;
  });
}

module.exports = { pinnedVersion, loadModule, readStdin, parseInput, Output, runProgram };
