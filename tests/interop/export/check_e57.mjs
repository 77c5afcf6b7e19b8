// Reads handscan's cloud.e57 with the npm `web-e57` package (a WebAssembly build of the Rust e57
// crate, independent of our code) and compares every point's coordinates and colour with the
// cloud.ply of the same export; checks the CRC-32C of every page with its own table (not our
// reader's code); and makes sure a page damaged on purpose is refused, as is ../shared/data's
// corrupt_crc.e57; with the fixture, the same for its export with ScaledInteger coordinates
// (within half a step); and follows the index packets to every data packet. Node 20: run with
// --experimental-wasm-modules.
import { existsSync, readFileSync } from 'node:fs';
import { convertE57 } from 'web-e57';

// Usage: check_e57.mjs FIXTURE_DIR [corrupt.e57] (the fixture's expected.json), or
//        check_e57.mjs EXPORT_DIR (any export with cloud.e57 and cloud.ply: the PLY is the truth).
const dir = process.argv[2];
const sharedE57 = process.argv[3];
const fail = (msg) => { console.error(`check_e57: ${msg}`); process.exit(1); };
const fixture = existsSync(`${dir}/expected.json`);
const expected = fixture ? JSON.parse(readFileSync(`${dir}/expected.json`, 'utf8')) : { dir };
// CRC-32C (Castagnoli), reflected polynomial 0x82F63B78, bit by bit into a table.
const table = new Uint32Array(256);
for (let i = 0; i < 256; ++i) {
  let c = i;
  for (let k = 0; k < 8; ++k) c = c & 1 ? (c >>> 1) ^ 0x82f63b78 : c >>> 1;
  table[i] = c >>> 0;
}
const crc32c = (bytes) => {
  let c = 0xffffffff;
  for (const b of bytes) c = table[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
};
if (crc32c(new TextEncoder().encode('123456789')) !== 0xe3069283) fail('CRC-32C table is wrong');

// The points' index packets (E2807 9.3.5), read with our own page arithmetic: the section
// header's indexPhysicalOffset leads, level by level, to one entry per data packet whose record
// numbers count the records of the packets before it (from their first bytestream's length).
function checkIndex(e57, xml, count, coordBytes) {
  const logicalRead = (physical, n) => {  // n bytes from a physical offset, skipping page CRCs
    const out = new Uint8Array(n);
    let p = physical;
    for (let k = 0; k < n; ++k) {
      if (p % 1024 === 1020) p += 4;
      out[k] = e57[p++];
    }
    return new DataView(out.buffer);
  };
  const after = (physical, n) => {  // the physical offset n logical bytes further on
    const logical = Math.floor(physical / 1024) * 1020 + (physical % 1024) + n;
    return Math.floor(logical / 1020) * 1024 + (logical % 1020);
  };
  const m = xml.match(/<points type="CompressedVector" fileOffset="(\d+)" recordCount="(\d+)"/);
  if (!m) fail('XML lacks the points CompressedVector');
  const section = logicalRead(Number(m[1]), 32);
  if (section.getUint8(0) !== 1) fail('the points section is not a compressed vector section');
  const dataOffset = Number(section.getBigUint64(16, true));
  const indexOffset = Number(section.getBigUint64(24, true));
  if (indexOffset === 0) fail('the points section has no index packet');
  const entries = [];
  let levels = 0;
  const walk = (offset, expectLevel) => {
    const h = logicalRead(offset, 16);
    if (h.getUint8(0) !== 0) fail(`no index packet at ${offset}`);
    const n = h.getUint16(4, true), level = h.getUint8(6);
    if (h.getUint16(2, true) + 1 !== 16 + 16 * n) fail(`index packet at ${offset}: length != 16 + 16 x ${n}`);
    if (expectLevel !== undefined && level !== expectLevel) fail(`index level ${level}, expected ${expectLevel}`);
    levels = Math.max(levels, level + 1);
    const body = logicalRead(after(offset, 16), 16 * n);
    for (let k = 0; k < n; ++k) {
      const record = Number(body.getBigUint64(16 * k, true));
      const target = Number(body.getBigUint64(16 * k + 8, true));
      if (level > 0) walk(target, level - 1); else entries.push([record, target]);
    }
  };
  walk(indexOffset);
  if (entries.length === 0 || entries[0][1] !== dataOffset) fail('the first index entry is not the first data packet');
  let records = 0;
  for (const [record, offset] of entries) {
    if (record !== records) fail(`index entry says record ${record} at ${offset}, the packets before hold ${records}`);
    const p = logicalRead(offset, 8);
    if (p.getUint8(0) !== 1) fail(`index entry ${offset} is no data packet`);
    records += p.getUint16(6, true) / coordBytes;  // the cartesianX bytestream's length
  }
  if (records !== count) fail(`the indexed data packets hold ${records} records, expected ${count}`);
  return `${entries.length} data packets indexed (${levels} level${levels > 1 ? 's' : ''})`;
}

// One export's cloud.e57 against its cloud.ply; `scale` > 0: ScaledInteger coordinates.
function checkExport(exportDir, scale) {
  const tol = scale > 0 ? scale / 2 + 1e-9 : 0;
  const e57 = new Uint8Array(readFileSync(`${exportDir}/cloud.e57`));
  // File header (E57 8.2) and every page's checksum, stored big-endian.
  const view = new DataView(e57.buffer, e57.byteOffset, e57.byteLength);
  if (new TextDecoder().decode(e57.subarray(0, 8)) !== 'ASTM-E57') fail('no ASTM-E57 signature');
  if (view.getUint32(8, true) !== 1 || view.getUint32(12, true) !== 0) fail('version is not 1.0');
  if (Number(view.getBigUint64(16, true)) !== e57.length) fail('filePhysicalLength != file size');
  if (Number(view.getBigUint64(40, true)) !== 1024) fail('page size is not 1024');
  if (e57.length % 1024 !== 0) fail('not a whole number of pages');
  const pages = e57.length / 1024;
  for (let p = 0; p < pages; ++p) {
    const page = e57.subarray(p * 1024, p * 1024 + 1024);
    const stored = new DataView(page.buffer, page.byteOffset + 1020, 4).getUint32(0, false);
    if (crc32c(page.subarray(0, 1020)) !== stored) fail(`page ${p}: CRC-32C mismatch`);
  }

  // The PLY of the same export: x y z float, r g b uchar, intensity ushort, time double (25 bytes).
  const ply = readFileSync(`${exportDir}/cloud.ply`);
  const headerEnd = ply.indexOf('end_header\n') + 'end_header\n'.length;
  const plyView = new DataView(ply.buffer, ply.byteOffset + headerEnd);
  const plyCount = (ply.length - headerEnd) / 25;
  if (expected.count === undefined) {  // no fixture: the PLY's count and bounds
    expected.count = plyCount;
    expected.min = [Infinity, Infinity, Infinity];
    expected.max = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < plyCount; ++i) {
      for (let a = 0; a < 3; ++a) {
        const v = plyView.getFloat32(i * 25 + 4 * a, true);
        expected.min[a] = Math.min(expected.min[a], v);
        expected.max[a] = Math.max(expected.max[a], v);
      }
    }
  }

  // Every point through the independent reader: "x y z r g b" per line.
  const lines = convertE57(e57, 'XYZ').trim().split('\n');
  if (lines.length !== expected.count || lines.length !== plyCount) fail(`${lines.length} points, expected ${expected.count} (PLY ${plyCount})`);
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  let uncoloured = 0;
  for (let i = 0; i < lines.length; ++i) {
    const v = lines[i].split(' ').map(Number);
    if (v.length !== 6) fail(`line ${i}: '${lines[i]}' is not x y z r g b`);
    for (let a = 0; a < 3; ++a) {
      const want = plyView.getFloat32(i * 25 + 4 * a, true);
      // Doubles are the PLY's floats exactly; scaled integers within half a step of them.
      if (Math.abs(v[a] - want) > tol) fail(`point ${i} axis ${a}: E57 ${v[a]} != PLY ${want} (tolerance ${tol})`);
      lo[a] = Math.min(lo[a], v[a]);
      hi[a] = Math.max(hi[a], v[a]);
    }
    // A point the camera did not see carries its laser grey (r = g = b = min(255, intensity / 16),
    // journal::laserGrey) and is written with isColorInvalid: its E57 colour is the reader's to fill.
    const rgb = [0, 1, 2].map((c) => plyView.getUint8(i * 25 + 12 + c));
    const grey = Math.min(255, Math.floor(plyView.getUint16(i * 25 + 15, true) / 16));
    if (rgb[0] === grey && rgb[1] === grey && rgb[2] === grey) {
      ++uncoloured;
      continue;
    }
    for (let c = 0; c < 3; ++c) {
      if (v[3 + c] !== rgb[c]) fail(`point ${i} colour ${c}: E57 ${v[3 + c]} != PLY ${rgb[c]}`);
    }
  }
  for (let a = 0; a < 3; ++a) {
    if (Math.abs(lo[a] - expected.min[a]) > 1e-6 + tol || Math.abs(hi[a] - expected.max[a]) > 1e-6 + tol) fail(`bounds axis ${a}: ${lo[a]}..${hi[a]}`);
  }

  // The XML as the crate sees it: one Data3D with our sensor, bounds and trajectory extension.
  const xml = convertE57(e57, 'XML');
  for (const want of [`recordCount="${expected.count}"`, '<sensorVendor type="String">handscan<',
    'xmlns:handscan=', '<timeStamp type="Float"']) {
    if (!xml.includes(want)) fail(`XML lacks ${want}`);
  }
  if (fixture && !xml.includes('<handscan:trajectory type="CompressedVector"')) fail('XML lacks the trajectory extension');
  const axisType = scale > 0 ? `<cartesianX type="ScaledInteger" minimum="-2147483648" maximum="2147483647" scale="${scale}"` : '<cartesianX type="Float" precision="double"';
  if (!xml.includes(axisType)) fail(`XML lacks ${axisType}`);
  const indexed = checkIndex(e57, xml, expected.count, scale > 0 ? 4 : 8);
  console.log(`check_e57: ${exportDir}: ${lines.length} points, coordinates ${scale > 0 ? `scaled integers of ${scale} m` : 'double'}, ${indexed}`);
  return { e57, pages, lines, uncoloured };

}

const { e57, pages, lines, uncoloured } = checkExport(expected.dir, 0);
if (expected.scaled_dir) checkExport(expected.scaled_dir, expected.scale);

// A flipped byte in a page of points (the middle page: the trajectory comes first, the XML last)
// must make the crate refuse the file, not return other points.
const damaged = e57.slice();
damaged[Math.floor(pages / 2) * 1024 + 200] ^= 0x40;
let refused = '';
try { convertE57(damaged, 'XYZ'); } catch (e) { refused = String(e); }
if (!refused) fail('a damaged page was read without an error');
console.log(`check_e57: the damaged copy is refused: ${refused}`);
if (sharedE57 && existsSync(sharedE57)) {
  let refusedShared = false;
  try { convertE57(new Uint8Array(readFileSync(sharedE57)), 'XYZ'); } catch { refusedShared = true; }
  if (!refusedShared) fail(`${sharedE57} (a corrupt page) was read without an error`);
}
console.log(`check_e57: ok, ${lines.length} points (${uncoloured} unseen by the camera: colour invalid), ${pages} pages with good CRC-32C, coordinates and colours match the PLY${expected.scaled_dir ? ' (scaled integers within half a step)' : ''}, index packets lead to every data packet, a damaged page is refused`);
