'use strict';
// vorobench executable: Delaunay triangulation with delaunator (Mapbox, Vladimir Agafonkin).
//
//   node triangulate.js CACHE      reads the vorobench text input on stdin, prints `i j k` lines
//                                  (one per triangle, counter-clockwise as delaunator gives them)
//                                  and one `time SECONDS` line (the constructor only)
//   node triangulate.js --version  prints the pinned delaunator version (needs no setup)
//
// CACHE is the folder where setup.js ran `npm ci` (it holds node_modules/delaunator).
// delaunator 5 is an ES module (index.js, importing robust-predicates); it is loaded with a
// dynamic import() of its resolved file, so the CommonJS/ESM question never arises.
//
// What delaunator does with degenerate input (read from its index.js):
// * no triangles at all when no third site gives a finite floating-point circumradius with
//   the two seed sites (all sites exactly collinear, and n < 3): `hull` is then the sites
//   sorted along the line;
// * orientation tests use the robust orient2d of robust-predicates, but the in-circle test
//   of the edge flips is plain floating point, so cocircular sets (grids) get one of the
//   valid triangulations and near-cocircular ones may keep a slightly non-Delaunay edge;
// * a site whose coordinates both differ by <= 2^-52 (absolute, not relative) from the
//   previous site in its distance-from-seed order is skipped as a near-duplicate: it is in
//   no triangle (only relevant at tiny coordinate scales).

const fs = require('fs');
const path = require('path');
const { createRequire } = require('module');
const { pathToFileURL } = require('url');

const PACKAGE = 'delaunator';

function pinnedVersion() {
  const pkg = JSON.parse(fs.readFileSync(path.join(__dirname, 'package.json'), 'utf8'));
  return pkg.dependencies[PACKAGE];
}

async function loadModule(cache) {
  const req = createRequire(path.join(path.resolve(cache), 'vorobench-resolve.js'));
  const entry = req.resolve(PACKAGE);
  return import(pathToFileURL(entry).href);
}

async function readStdin() {
  const chunks = [];
  for await (const chunk of process.stdin) chunks.push(chunk);
  return Buffer.concat(chunks).toString('latin1');
}

// Parse `n [weighted]` then n lines `x y`; numbers are Python repr strings, which Number()
// converts exactly (correctly rounded, hence round-trip exact).
function parseInput(text) {
  const len = text.length;
  let pos = 0;
  const lineEnd = text.indexOf('\n');
  const header = (lineEnd < 0 ? text : text.slice(0, lineEnd)).trim().split(/\s+/);
  if (header.length === 0 || header[0] === '') throw new Error('empty input');
  const n = Number(header[0]);
  if (!Number.isInteger(n) || n < 0) throw new Error(`bad site count: ${header[0]}`);
  if (header.length > 1) {
    if (header[1] === 'weighted') throw new Error('weighted sites are not supported by delaunator');
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

async function main() {
  const args = process.argv.slice(2);
  if (args[0] === '--version') {
    process.stdout.write(pinnedVersion() + '\n');
    return;
  }
  const cache = args[0] || process.env.VOROBENCH_CACHE;
  if (!cache) throw new Error('usage: node triangulate.js CACHE_DIR < input');
  const Delaunator = (await loadModule(cache)).default;

  const { coords } = parseInput(await readStdin());

  const t0 = process.hrtime.bigint();
  const d = new Delaunator(coords);
  const t1 = process.hrtime.bigint();

  const tri = d.triangles;
  const m = tri.length;
  const out = new Output(m * 8 + 64);
  for (let e = 0; e < m; e += 3) {
    out.ensure(40);
    out.int(tri[e]);
    out.byte(32);
    out.int(tri[e + 1]);
    out.byte(32);
    out.int(tri[e + 2]);
    out.byte(10);
  }
  out.text(`time ${Number(t1 - t0) / 1e9}\n`);
  out.flush();
}

main().catch((err) => {
  process.stderr.write(`delaunator: ${err && err.stack ? err.stack : err}\n`);
  process.exitCode = 1;
});
