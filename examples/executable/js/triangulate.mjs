// A complete vorobench executable in JavaScript: Delaunay triangles from delaunator.
//   stdin:  "n" then n lines "x y" (Python repr floats, which Number() reads back exactly)
//   stdout: one "i j k" line per triangle, then "time SECONDS" (the construction alone)
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { pathToFileURL } from "node:url";

// setup installed delaunator into the cache folder, given as the first argument
const cache = process.argv[2];
const entry = createRequire(`${cache}/`).resolve("delaunator");
const { default: Delaunator } = await import(pathToFileURL(entry).href);

const words = readFileSync(0, "latin1").split(/\s+/).filter(Boolean);
const n = Number(words[0]);
const coords = Float64Array.from(words.slice(1, 1 + 2 * n), Number);

const start = process.hrtime.bigint();
const { triangles } = new Delaunator(coords);   // no triangles when all sites are collinear
const seconds = Number(process.hrtime.bigint() - start) / 1e9;

const lines = [];
for (let t = 0; t < triangles.length; t += 3) {
  lines.push(`${triangles[t]} ${triangles[t + 1]} ${triangles[t + 2]}`);
}
lines.push(`time ${seconds}`);
process.stdout.write(lines.join("\n") + "\n");
