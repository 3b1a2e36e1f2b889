// Converts the npm "bunny" package (Stanford bunny) to a Wavefront OBJ on stdout, with
// area-weighted smooth vertex normals.
const b = require("bunny");
const P = b.positions, C = b.cells;
const N = P.map(() => [0, 0, 0]);
for (const [i, j, k] of C) {
  const u = P[j].map((x, a) => x - P[i][a]), v = P[k].map((x, a) => x - P[i][a]);
  const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
  for (const idx of [i, j, k]) for (let a = 0; a < 3; a++) N[idx][a] += n[a];
}
const f = (x) => +x.toFixed(6);
const out = ["# Stanford Bunny (Stanford 3D Scanning Repository), from npm package bunny@1.0.1.",
  "# See README.md in this folder for attribution.",
  `# ${P.length} vertices, ${C.length} triangles, area-weighted vertex normals.`];
for (const p of P) out.push(`v ${p.map(f).join(" ")}`);
for (const n of N) { const l = Math.hypot(...n) || 1; out.push(`vn ${n.map(x => f(x / l)).join(" ")}`); }
for (const c of C) out.push(`f ${c.map(i => `${i + 1}//${i + 1}`).join(" ")}`);
process.stdout.write(out.join("\n") + "\n");
