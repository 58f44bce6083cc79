'use strict';
// vorobench executable: Delaunay triangulation with delaunator (Mapbox, Vladimir Agafonkin).
//
//   node triangulate.js CACHE      reads the vorobench text input on stdin, prints `i j k` lines
//                                  (one per triangle, counter-clockwise as delaunator gives them)
//                                  and one `time SECONDS` line (the constructor only)
//   node triangulate.js --version  prints the pinned delaunator version (needs no setup)
//
// CACHE is the folder where ../node-common/setup.js ran `npm ci` (it holds
// node_modules/delaunator). delaunator 5 is an ES module (index.js, importing
// robust-predicates); it is loaded with a dynamic import() of its resolved file, so the
// CommonJS/ESM question never arises. The command line, input parsing, output buffer and error
// handling are ../node-common/protocol.js.
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

const path = require('path');
const { Output, runProgram } = require(path.join(__dirname, '..', 'node-common', 'protocol.js'));

runProgram('delaunator', __filename, (lib, { coords }) => {
  const Delaunator = lib.default;

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
});
