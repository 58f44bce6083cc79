'use strict';
// vorobench executable: Voronoi diagram with d3-delaunay (Observable / Mike Bostock; its
// triangulation is Mapbox's delaunator, bundled into d3-delaunay's dist file).
//
//   node voronoi.js CACHE      reads the vorobench text input on stdin and prints the diagram
//                              in vorobench's `voronoi` format plus one `time SECONDS` line
//                              (new Delaunay(coords) + .voronoi(bounds) only)
//   node voronoi.js --version  prints the pinned d3-delaunay version (needs no setup)
//
// CACHE is the folder where ../node-common/setup.js ran `npm ci` (it holds
// node_modules/d3-delaunay). The package's default export is dist/d3-delaunay.mjs, an ES
// module; it is loaded with a dynamic import() of the file that the package's `exports`
// resolve to. The command line, input parsing, output buffer and error handling are
// ../node-common/protocol.js.
//
// Output, from d3's own arrays (nothing recomputed here):
// * `v x y` for every triangle t: x = voronoi.circumcenters[2t], y = ...[2t + 1] (vertex id t);
// * for each Delaunay half-edge e with twin h = halfedges[e] and e < h:
//   `e i j a b`, i = triangles[e], j = triangles[next(e)], a = floor(e / 3), b = floor(h / 3);
// * for each hull half-edge (halfedges[e] == -1): `e i j a -1` (a ray from vertex a).
// Floats are printed with JavaScript's shortest round-trip form (String(x)), which is exact.
//
// What d3-delaunay 6 does with degenerate input (read from its source, delaunay.js and
// voronoi.js, identical in 6.0.4 and 6.0.6):
// * Collinear: in Delaunay._init, when the hull has > 2 sites and every triangle has
//   (c - a) x (b - a) <= 1e-10 (an ABSOLUTE threshold; vacuously true when delaunator
//   returned no triangles, which it does for exactly collinear sites), d3 sets
//   `delaunay.collinear` = the site indices sorted by x then y, moves every site IN PLACE by
//   up to r = 1e-8 * |last - first| (x += sin(x + y) r, y += cos(x - y) r) and triangulates
//   the jittered sites again; its neighbors() then reports the consecutive entries of
//   `collinear`. We print that chain, `e i j -1 -1` per consecutive pair, and no vertices (the
//   circumcentres of the jittered triangulation are artefacts of the jitter).
// * One or two distinct sites (hull length <= 2): d3 replaces the triangulation by a fake
//   triangle [h0, h1, h1] with no twins; we print `e h0 h1 -1 -1` for two sites, nothing for
//   fewer (n < 2).
// * Degenerate (flat) triangles: in Voronoi._init, when 2 * ((b - a) x (c - a)) has
//   absolute value < 1e-9 (ABSOLUTE again, so it also catches tiny but fine triangles of
//   small-scale input), the circumcentre is not computed: d3 puts the vertex at the midpoint
//   of a and c plus 1e9 * the perpendicular (-(c - a).y, (c - a).x), i.e. about 1e9 * |c - a|
//   away, on the side away from the barycentre of the hull's sites ("at infinity"; if that
//   side test gives 0 the vertex is the midpoint itself). We print that vertex as d3 has it.

const path = require('path');
const { Output, runProgram } = require(path.join(__dirname, '..', 'node-common', 'protocol.js'));

function next(e) {
  return e % 3 === 2 ? e - 2 : e + 1;
}

function printChain(out, chain) {
  for (let k = 1; k < chain.length; k++) {
    out.ensure(40);
    out.byte(101); // 'e'
    out.byte(32);
    out.int(chain[k - 1]);
    out.byte(32);
    out.int(chain[k]);
    out.text(' -1 -1\n');
  }
}

runProgram('d3-delaunay', __filename, ({ Delaunay }, { n, coords }) => {
  // Bounds only matter to d3's clipping (cell polygons, rendering), which is not used here;
  // give it the sites' bounding box (the unit square when there are no sites).
  let xmin = Infinity, ymin = Infinity, xmax = -Infinity, ymax = -Infinity;
  for (let i = 0; i < n; i++) {
    const x = coords[2 * i], y = coords[2 * i + 1];
    if (x < xmin) xmin = x;
    if (x > xmax) xmax = x;
    if (y < ymin) ymin = y;
    if (y > ymax) ymax = y;
  }
  const bounds = n > 0 ? [xmin, ymin, xmax, ymax] : [0, 0, 1, 1];

  const t0 = process.hrtime.bigint();
  const delaunay = new Delaunay(coords);
  const voronoi = delaunay.voronoi(bounds);
  const t1 = process.hrtime.bigint();

  const { triangles, halfedges, hull } = delaunay;
  let out;
  if (delaunay.collinear) {
    out = new Output(n * 24 + 64);
    printChain(out, delaunay.collinear);
  } else if (hull.length <= 2) {
    out = new Output(64);
    printChain(out, hull);
  } else {
    const cc = voronoi.circumcenters;
    const m = triangles.length;
    out = new Output(m * 32 + 64);
    // vertices: lines joined in blocks of 1024 (fewer Buffer writes)
    let block = '';
    for (let t = 0, nt = m / 3; t < nt; t++) {
      block += `v ${cc[2 * t]} ${cc[2 * t + 1]}\n`;
      if ((t & 1023) === 1023) {
        out.text(block);
        block = '';
      }
    }
    out.text(block);
    for (let e = 0; e < m; e++) {
      const h = halfedges[e];
      if (h !== -1 && h < e) continue;
      out.ensure(64);
      out.byte(101); // 'e'
      out.byte(32);
      out.int(triangles[e]);
      out.byte(32);
      out.int(triangles[next(e)]);
      out.byte(32);
      out.int(Math.floor(e / 3));
      out.byte(32);
      out.int(h === -1 ? -1 : Math.floor(h / 3));
      out.byte(10);
    }
  }
  out.text(`time ${Number(t1 - t0) / 1e9}\n`);
  out.flush();
});
