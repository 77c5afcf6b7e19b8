// Opens a `handscan replay --viz` file with independent readers - @mcap/core for the MCAP,
// protobufjs for the messages, built from nothing but the FileDescriptorSet each channel's schema
// embeds - and checks it against what the replay wrote beside it:
//   every channel is protobuf with its Foxglove (or handscan.msgs) type, every message decodes;
//   /pose equals trajectory.tum pose by pose, and /tf's world->body equals /pose;
//   /sweep and /map are PointClouds with the x y z intensity rgb layout, /sweep's points add up
//   to stats.json's registered points, /map grows with the sweeps;
//   each image's own header (PNG IHDR, JPEG SOF) gives the size its CameraCalibration states and
//   the size the camchain gives the camera;
//   /imu, /status and the ground truth carry what they say.
//
//   the Foxglove layout (tools/foxglove/handscan-layout.json) names only topics the file has and
//   plots only fields its messages carry.
// With --journal N, a viz file written from a journal (`handscan export --format mcap`, `handscan
// hil --viz`): /pose against DIR/trajectory.tum, /sweep's points add up to N, no /imu, /status or
// body->laser (the journal keeps none), cameras and ground truth checked where present (hil).
//
// usage: node check_viz.mjs VIZ.mcap REPLAY_DIR TRACK_WxH COLOUR_WxH LAYOUT.json [--journal N]
import { readFile } from "node:fs/promises";
import { McapIndexedReader } from "@mcap/core";
import { decompress } from "fzstd";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";

const [file, replayDir, trackSize, colourSize, layoutFile, journalFlag, journalPoints] = process.argv.slice(2);
const journal = journalFlag === "--journal";
const failures = [];
const check = (ok, what) => {
  if (!ok) failures.push(what);
};

const bytes = new Uint8Array(await readFile(file));
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const decompressHandlers = { zstd: (data, size) => decompress(data, new Uint8Array(Number(size))) };
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });

// ---- Channels and schemas ------------------------------------------------------------------------
const expectedTypes = {
  "/pose": "foxglove.PoseInFrame",
  "/path": "foxglove.PosesInFrame",
  "/tf": "foxglove.FrameTransforms",
  "/sweep": "foxglove.PointCloud",
  "/map": "foxglove.PointCloud",
  "/imu": "handscan.msgs.Imu",
  "/status": "handscan.msgs.PipelineStatus",
  "/camera/track": "foxglove.CompressedImage",
  "/camera/track/calibration": "foxglove.CameraCalibration",
  "/camera/colour": "foxglove.CompressedImage",
  "/camera/colour/calibration": "foxglove.CameraCalibration",
  "/groundtruth/pose": "foxglove.PoseInFrame",
};
const typeOf = new Map(); // channel id -> protobufjs Type
const topicOf = new Map();
for (const channel of reader.channelsById.values()) {
  topicOf.set(channel.id, channel.topic);
  const schema = reader.schemasById.get(channel.schemaId);
  check(channel.messageEncoding === "protobuf", `${channel.topic}: message encoding ${channel.messageEncoding}`);
  check(schema && schema.encoding === "protobuf", `${channel.topic}: schema encoding ${schema?.encoding}`);
  check(schema && schema.name === expectedTypes[channel.topic], `${channel.topic}: schema ${schema?.name}`);
  if (!schema) continue;
  // The schema alone: a FileDescriptorSet decoded by protobufjs' own descriptor.proto.
  const set = descriptor.FileDescriptorSet.decode(schema.data);
  const root = protobuf.Root.fromDescriptor(set);
  typeOf.set(channel.id, root.lookupType(schema.name));
}
// A journal holds poses and points only; the cameras and the ground truth come with hil's recording.
const journalOptional = ["/imu", "/status", "/camera/track", "/camera/track/calibration", "/camera/colour",
  "/camera/colour/calibration", "/groundtruth/pose"];
const required = Object.keys(expectedTypes).filter((t) => !journal || !journalOptional.includes(t));
for (const topic of required) {
  check([...topicOf.values()].includes(topic), `no ${topic} channel`);
}

// ---- Every message, decoded -------------------------------------------------------------------
const byTopic = {};
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const topic = topicOf.get(m.channelId);
  const type = typeOf.get(m.channelId);
  let msg;
  try {
    msg = type.toObject(type.decode(m.data), { longs: Number, defaults: true });
  } catch (e) {
    check(false, `${topic}: message at ${m.logTime} does not decode: ${e.message}`);
    continue;
  }
  (byTopic[topic] ??= []).push({ logTime: m.logTime, msg });
}
const count = (t) => (byTopic[t] ?? []).length;
for (const t of required) check(count(t) > 0, `${t}: no messages`);
if (journal) check(count("/imu") === 0 && count("/status") === 0, "a journal's viz has /imu or /status messages");
const stamp = (ts) => BigInt(ts.seconds) * 1000000000n + BigInt(ts.nanos);
for (const [t, msgs] of Object.entries(byTopic)) {
  if (t === "/tf") continue;
  for (const { logTime, msg } of msgs) {
    check(stamp(msg.timestamp) === logTime, `${t}: timestamp ${stamp(msg.timestamp)} != log time ${logTime}`);
  }
}

// ---- /pose against trajectory.tum, /tf against /pose -------------------------------------------
const tum = (await readFile(`${replayDir}/trajectory.tum`, "utf8"))
  .split("\n")
  .filter((l) => l && !l.startsWith("#"))
  .map((l) => l.trim().split(/\s+/).map(Number));
const poses = byTopic["/pose"] ?? [];
check(poses.length === tum.length, `/pose has ${poses.length} poses, trajectory.tum ${tum.length}`);
let worstPos = 0;
let worstRot = 0;
for (let i = 0; i < Math.min(poses.length, tum.length); ++i) {
  const { msg } = poses[i];
  const [t, x, y, z, qx, qy, qz, qw] = tum[i];
  check(msg.frame_id === "world", `/pose frame ${msg.frame_id}`);
  check(Math.abs(Number(stamp(msg.timestamp)) / 1e9 - t) < 2e-9 * Math.max(1, t), `/pose ${i}: time ${stamp(msg.timestamp)} vs TUM ${t}`);
  const p = msg.pose.position;
  const q = msg.pose.orientation;
  worstPos = Math.max(worstPos, Math.hypot(p.x - x, p.y - y, p.z - z));
  const dot = Math.abs(q.x * qx + q.y * qy + q.z * qz + q.w * qw); // q and -q: one rotation
  worstRot = Math.max(worstRot, 1 - dot);
}
// trajectory.tum prints positions to 1e-6 m and quaternions to 1e-9.
check(worstPos < 2e-6, `/pose vs trajectory.tum: position off by ${worstPos} m`);
check(worstRot < 1e-8, `/pose vs trajectory.tum: rotation off by 1 - |q.q'| = ${worstRot}`);

const poseAt = new Map(poses.map(({ logTime, msg }) => [logTime, msg.pose]));
const frames = new Set();
let tfWithPose = 0;
let tfWithLaser = 0;
let gtAlignment;
for (const { logTime, msg } of byTopic["/tf"] ?? []) {
  for (const tr of msg.transforms) {
    frames.add(`${tr.parent_frame_id}->${tr.child_frame_id}`);
    if (tr.parent_frame_id === "world" && tr.child_frame_id === "body") {
      const pose = poseAt.get(stamp(tr.timestamp));
      check(pose !== undefined, `/tf world->body at ${stamp(tr.timestamp)} has no /pose`);
      if (pose) {
        ++tfWithPose;
        check(Math.hypot(pose.position.x - tr.translation.x, pose.position.y - tr.translation.y, pose.position.z - tr.translation.z) < 1e-12, "/tf world->body != /pose");
      }
    }
    if (tr.parent_frame_id === "body" && tr.child_frame_id === "laser") ++tfWithLaser;
    if (tr.child_frame_id === "groundtruth_world" && !gtAlignment) gtAlignment = { t: stamp(tr.timestamp), tr };
    const q = tr.rotation;
    check(Math.abs(Math.hypot(q.x, q.y, q.z, q.w) - 1) < 1e-9, `/tf ${tr.child_frame_id}: rotation not unit`);
  }
  check(logTime > 0n, "/tf log time");
}
check(tfWithPose === poses.length, `/tf: ${tfWithPose} world->body transforms for ${poses.length} poses`);
// The encoder covers the poses but the first few (before its first sample).
if (!journal) check(tfWithLaser >= 0.95 * poses.length, `/tf: body->laser with only ${tfWithLaser} of ${poses.length} poses`);
const wantedFrames = ["world->body", "body->imu", "body->camera_track", "body->camera_colour"];
if (!journal) wantedFrames.push("body->laser");
if (count("/groundtruth/pose") > 0) wantedFrames.push("world->groundtruth_world");
for (const f of wantedFrames) {
  check(frames.has(f), `/tf has no ${f}`);
}

// /path once per sweep: the trajectory so far, each pose one of /pose's, the newest last.
const paths = byTopic["/path"] ?? [];
const sweepsOrWindows = journal ? count("/sweep") : count("/status");
check(paths.length === sweepsOrWindows, `/path: ${paths.length} messages for ${sweepsOrWindows} sweeps`);
const key = (p) => `${p.position.x},${p.position.y},${p.position.z}`;
const poseKeys = new Set(poses.map(({ msg }) => key(msg.pose)));
for (const { msg } of paths) {
  check(msg.frame_id === "world", `/path frame ${msg.frame_id}`);
  check(msg.poses.length >= 1 && msg.poses.every((p) => poseKeys.has(key(p))), "/path holds a pose that is not on /pose");
}
const lastPath = paths.length ? paths[paths.length - 1].msg.poses : [];
check(lastPath.length >= 10, `/path ends with only ${lastPath.length} poses`);

// ---- Point clouds -----------------------------------------------------------------------------
const layout = [
  ["x", 0, 7],
  ["y", 4, 7],
  ["z", 8, 7],
  ["intensity", 12, 7],
  ["rgb", 16, 5],
];
const cloudPoints = (topic, msg) => {
  check(msg.frame_id === "world", `${topic}: frame ${msg.frame_id}`);
  check(msg.point_stride === 20, `${topic}: point stride ${msg.point_stride}`);
  const fields = msg.fields.map((f) => [f.name, f.offset, f.type]);
  check(JSON.stringify(fields) === JSON.stringify(layout), `${topic}: fields ${JSON.stringify(fields)}`);
  check(msg.data.length % 20 === 0, `${topic}: ${msg.data.length} data bytes, not whole points`);
  const view = new DataView(msg.data.buffer, msg.data.byteOffset, msg.data.byteLength);
  const n = msg.data.length / 20;
  for (let i = 0; i < n; i += 97) {
    for (const off of [0, 4, 8, 12]) check(Number.isFinite(view.getFloat32(i * 20 + off, true)), `${topic}: point ${i} not finite`);
    check(view.getUint32(i * 20 + 16, true) <= 0xffffff, `${topic}: point ${i} rgb has bits above 0x00RRGGBB`);
  }
  return n;
};
const stats = journal ? {} : JSON.parse(await readFile(`${replayDir}/stats.json`, "utf8"));
const expectedPoints = journal ? Number(journalPoints) : stats.registered_points;
const sweepPoints = (byTopic["/sweep"] ?? []).reduce((sum, { msg }) => sum + cloudPoints("/sweep", msg), 0);
check(sweepPoints === expectedPoints, `/sweep: ${sweepPoints} points, expected ${expectedPoints} (${journal ? "the journal's" : "stats.json registered"})`);
let mapBefore = 0;
let mapPoints = 0;
for (const { msg } of byTopic["/map"] ?? []) {
  mapPoints = cloudPoints("/map", msg);
  check(mapPoints >= mapBefore, `/map shrank from ${mapBefore} to ${mapPoints} points`);
  mapBefore = Math.max(mapBefore, mapPoints);
}
check(mapPoints > 0 && mapPoints < sweepPoints, `/map: ${mapPoints} points for ${sweepPoints} registered (5 cm voxels)`);
// A journal's viz shows /map every 2 s of its 0.5 s windows.
if (journal) check(count("/map") >= 1 && count("/map") <= count("/sweep"), "/map at most once per window");
else check(count("/map") === count("/sweep"), "/map once per sweep");

// ---- Images and their calibration --------------------------------------------------------------
const imageSize = (data, format) => {
  if (format === "png") {
    check(data[1] === 0x50 && data[2] === 0x4e && data[3] === 0x47, "png signature");
    const v = new DataView(data.buffer, data.byteOffset);
    return [v.getUint32(16), v.getUint32(20)]; // IHDR
  }
  check(format === "jpeg", `image format ${format}`);
  check(data[0] === 0xff && data[1] === 0xd8, "jpeg SOI");
  for (let i = 2; i + 9 < data.length; ) {
    if (data[i] !== 0xff) return [0, 0];
    const marker = data[i + 1];
    const length = (data[i + 2] << 8) | data[i + 3];
    if (marker >= 0xc0 && marker <= 0xc3) return [(data[i + 7] << 8) | data[i + 8], (data[i + 5] << 8) | data[i + 6]];
    i += 2 + length;
  }
  return [0, 0];
};
for (const [camera, expected] of [["track", trackSize], ["colour", colourSize]]) {
  const calibrations = new Map((byTopic[`/camera/${camera}/calibration`] ?? []).map(({ logTime, msg }) => [logTime, msg]));
  const [ew, eh] = expected.split("x").map(Number);
  for (const { logTime, msg } of byTopic[`/camera/${camera}`] ?? []) {
    const [w, h] = imageSize(msg.data, msg.format);
    const cal = calibrations.get(logTime);
    check(cal !== undefined, `/camera/${camera} at ${logTime}: no calibration`);
    check(msg.frame_id === `camera_${camera}`, `/camera/${camera} frame ${msg.frame_id}`);
    if (!cal) continue;
    check(w === cal.width && h === cal.height, `/camera/${camera}: image ${w}x${h}, calibration ${cal.width}x${cal.height}`);
    check(w === ew && h === eh, `/camera/${camera}: image ${w}x${h}, camchain ${expected}`);
    check(cal.K.length === 9 && cal.P.length === 12 && cal.R.length === 9, `/camera/${camera}: K, P, R sizes`);
    check(cal.K[0] > 0 && cal.K[2] > 0 && cal.K[2] < w && cal.K[5] < h && cal.K[8] === 1, `/camera/${camera}: K ${cal.K}`);
  }
}
check(calibrationCount("track") === count("/camera/track"), "one calibration per tracking frame");
function calibrationCount(camera) {
  return count(`/camera/${camera}/calibration`);
}

// ---- IMU, status, ground truth ----------------------------------------------------------------
if (!journal) {
check(count("/imu") === stats.imu.samples, `/imu: ${count("/imu")} samples, stats.json ${stats.imu.samples}`);
const g = (byTopic["/imu"] ?? []).map(({ msg }) => Math.hypot(msg.linear_acceleration_mps2.x, msg.linear_acceleration_mps2.y, msg.linear_acceleration_mps2.z));
const meanG = g.reduce((a, b) => a + b, 0) / Math.max(1, g.length);
check(Math.abs(meanG - 9.81) < 0.5, `/imu: mean |specific force| ${meanG} m/s^2, not gravity`);
check(count("/status") === stats.sweeps, `/status: ${count("/status")} messages for ${stats.sweeps} sweeps`);
// The first sweep has no map to match; the last (partial, at the end) has no samples after it.
for (const { msg } of (byTopic["/status"] ?? []).slice(1, -1)) {
  const solved = [msg.solved_rx, msg.solved_ry, msg.solved_rz, msg.solved_tx, msg.solved_ty, msg.solved_tz];
  check(solved.every((v) => v === 0 || v === 1) && solved.reduce((a, b) => a + b) === msg.solved_count, `/status: solved ${solved} vs count ${msg.solved_count}`);
  check(msg.degeneracy_eigenvalues.length === 6, `/status: ${msg.degeneracy_eigenvalues.length} eigenvalues`);
  check(Math.abs(msg.imu_hz - 200) < 40 && Math.abs(msg.laser_scans_hz - 40) < 10, `/status: rates imu ${msg.imu_hz} laser ${msg.laser_scans_hz}`);
}
}
const gt = byTopic["/groundtruth/pose"] ?? [];
check(gt.every(({ msg }) => msg.frame_id === "groundtruth_world"), "/groundtruth/pose frame");
if (gtAlignment && poses.length > 0) {
  // world->groundtruth_world places the ground truth on the first pose it covers: there they agree.
  const apply = (tr, p) => {
    const { x, y, z, w } = tr.rotation;
    const [vx, vy, vz] = [p.x, p.y, p.z];
    const tx = 2 * (y * vz - z * vy), ty = 2 * (z * vx - x * vz), tz = 2 * (x * vy - y * vx);
    return [vx + w * tx + (y * tz - z * ty) + tr.translation.x, vy + w * ty + (z * tx - x * tz) + tr.translation.y, vz + w * tz + (x * ty - y * tx) + tr.translation.z];
  };
  const nearest = (list, t) => list.reduce((best, e) => (abs(e.logTime - t) < abs(best.logTime - t) ? e : best));
  const abs = (v) => (v < 0n ? -v : v);
  const truth = nearest(gt, poses[0].logTime);
  const p = apply(gtAlignment.tr, truth.msg.pose.position);
  const e = poses[0].msg.pose.position;
  const d = Math.hypot(p[0] - e.x, p[1] - e.y, p[2] - e.z);
  check(d < 1e-6, `ground truth aligned at the first pose is ${d} m from it`);
  // ... and later the estimate stays near it (the office walk drifts centimetres, not metres).
  const last = poses[poses.length - 1];
  const pl = apply(gtAlignment.tr, nearest(gt, last.logTime).msg.pose.position);
  const dl = Math.hypot(pl[0] - last.msg.pose.position.x, pl[1] - last.msg.pose.position.y, pl[2] - last.msg.pose.position.z);
  check(dl < 0.5, `last pose ${dl} m from the aligned ground truth`);
  console.log(`ground truth: last pose ${dl.toFixed(3)} m from the aligned ground truth`);
}

// ---- The layout: its topics exist, its plot paths resolve in the decoded messages -------------
const foxgloveLayout = JSON.parse(await readFile(layoutFile, "utf8"));
for (const [panel, config] of journal ? [] : Object.entries(foxgloveLayout.configById)) {
  const topics = [...Object.keys(config.topics ?? {})];
  if (config.imageMode?.imageTopic) topics.push(config.imageMode.imageTopic, config.imageMode.calibrationTopic);
  for (const t of topics) check(count(t) > 0, `layout ${panel}: topic ${t} is not in the file`);
  for (const { value } of config.paths ?? []) {
    const [topic, ...fields] = value.split(".");
    let v = byTopic[topic]?.[1]?.msg;
    for (const f of fields) v = v?.[f];
    check(v !== undefined && v !== null, `layout ${panel}: plot path ${value} resolves to nothing`);
  }
}

const summary = Object.entries(byTopic).map(([t, m]) => `${t} ${m.length}`).join(", ");
if (failures.length) {
  console.error(`check_viz: ${failures.length} failures (${[...new Set(failures)].length} distinct):`);
  for (const f of [...new Set(failures)].slice(0, 30)) console.error(`  ${f}`);
  process.exit(1);
}
console.log(`check_viz: ${file}: every message decodes from its embedded descriptors (${summary}); ` +
  `${sweepPoints} sweep points = ${journal ? "the journal's" : "stats.json"}; /map ${mapPoints} points; /pose = trajectory.tum (${worstPos.toExponential(1)} m)`);
