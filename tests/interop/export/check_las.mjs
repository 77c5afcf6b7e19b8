// Reads handscan's cloud.las with the npm `copc` package's LAS reader (independent of our code)
// and compares point count, header bounds, per-point bounds and colours with expected.json.
import { readFileSync } from 'node:fs';
import { Las } from 'copc';

const dir = process.argv[2];
const expected = JSON.parse(readFileSync(`${dir}/expected.json`, 'utf8'));
const buffer = new Uint8Array(readFileSync(`${expected.dir}/cloud.las`));
const header = Las.Header.parse(buffer);
const fail = (msg) => { console.error(`check_las: ${msg}`); process.exit(1); };
if (header.majorVersion !== 1 || header.minorVersion !== 4) fail(`version ${header.majorVersion}.${header.minorVersion}`);
if (header.pointDataRecordFormat !== 7) fail(`point format ${header.pointDataRecordFormat}`);
if (header.pointCount !== expected.count) fail(`point count ${header.pointCount} != ${expected.count}`);
const tol = 1e-3;
for (let i = 0; i < 3; ++i) {
  if (Math.abs(header.min[i] - expected.min[i]) > tol) fail(`header min[${i}] ${header.min[i]} != ${expected.min[i]}`);
  if (Math.abs(header.max[i] - expected.max[i]) > tol) fail(`header max[${i}] ${header.max[i]} != ${expected.max[i]}`);
}
const view = Las.View.create(buffer.subarray(header.pointDataOffset), header);
const get = ['X', 'Y', 'Z', 'Red', 'Green', 'Blue', 'GpsTime'].map((d) => view.getter(d));
const lo = [Infinity, Infinity, Infinity];
const hi = [-Infinity, -Infinity, -Infinity];
const sum = [0, 0, 0];
for (let p = 0; p < view.pointCount; ++p) {
  for (let i = 0; i < 3; ++i) {
    const v = get[i](p);
    lo[i] = Math.min(lo[i], v);
    hi[i] = Math.max(hi[i], v);
    sum[i] += get[3 + i](p) / 257;
  }
}
if (view.pointCount !== expected.count) fail(`view has ${view.pointCount} points`);
for (let i = 0; i < 3; ++i) {
  if (Math.abs(lo[i] - expected.min[i]) > tol || Math.abs(hi[i] - expected.max[i]) > tol) fail(`point bounds axis ${i}: ${lo[i]}..${hi[i]}`);
  if (Math.abs(sum[i] - expected.sum_rgb[i]) > 0.5) fail(`colour sum ${i}: ${sum[i]} != ${expected.sum_rgb[i]}`);
}
const first = [get[3](0) / 257, get[4](0) / 257, get[5](0) / 257];
if (first.some((v, i) => v !== expected.first_rgb[i])) fail(`first colour ${first} != ${expected.first_rgb}`);
console.log(`check_las: ok, ${view.pointCount} points, bounds and colours match`);
