// Opens a recording written by handscan with independent MCAP readers (@mcap/core's indexed and
// streaming readers, zstd through fzstd) and checks it against what the writer says it wrote:
// channel names, message counts per topic, CRCs (chunks, summary, data section) and that the
// file holds both zstd and uncompressed chunks.
//
// usage: node check_recording.mjs REC.mcap REC.mcap.expected.json
import { readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { crc32 } from "@foxglove/crc";
import { decompress } from "fzstd";

const [file, expectedFile] = process.argv.slice(2);
const expected = JSON.parse(await readFile(expectedFile, "utf8"));
const bytes = new Uint8Array(await readFile(file));
const decompressHandlers = { zstd: (data, size) => decompress(data, new Uint8Array(Number(size))) };
const failures = [];
const check = (ok, what) => {
  if (!ok) failures.push(what);
};

// 1. Indexed reader: footer, summary (CRC checked by the reader), chunk indexes.
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
const topics = [...reader.channelsById.values()].map((c) => c.topic).sort();
check(
  JSON.stringify(topics) === JSON.stringify(Object.keys(expected.channels).sort()),
  `channels ${topics} != ${Object.keys(expected.channels)}`,
);
const indexedCounts = {};
let last = -1n;
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const topic = reader.channelsById.get(m.channelId).topic;
  indexedCounts[topic] = (indexedCounts[topic] ?? 0) + 1;
  check(m.logTime >= last, `messages out of log-time order at ${m.logTime}`);
  last = m.logTime;
}
for (const [topic, n] of Object.entries(expected.channels)) {
  check(indexedCounts[topic] === n, `indexed reader: ${topic} has ${indexedCounts[topic]} messages, expected ${n}`);
  const id = [...reader.channelsById.values()].find((c) => c.topic === topic).id;
  check(reader.statistics.channelMessageCounts.get(id) === BigInt(n), `statistics count for ${topic}`);
}
check(reader.statistics.messageCount === BigInt(expected.messages), "statistics message count");
check(reader.chunkIndexes.length === expected.chunks, `${reader.chunkIndexes.length} chunk indexes, expected ${expected.chunks}`);
const compressions = new Set(reader.chunkIndexes.map((c) => c.compression));
check(compressions.has("zstd") && compressions.has(""), `chunk compressions ${[...compressions]}: want zstd and ""`);

// 2. Streaming reader over the whole file: every record, chunk CRCs validated.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
const streamCounts = {};
const channelTopics = new Map();
let dataEnd;
let record;
let offsetOfDataEnd = 0;
while ((record = stream.nextRecord())) {
  if (record.type === "Channel") channelTopics.set(record.id, record.topic);
  if (record.type === "Message") {
    const topic = channelTopics.get(record.channelId);
    streamCounts[topic] = (streamCounts[topic] ?? 0) + 1;
  }
  if (record.type === "DataEnd") dataEnd = record;
}
check(stream.done(), "stream reader did not reach the end magic");
for (const [topic, n] of Object.entries(expected.channels)) {
  check(streamCounts[topic] === n, `stream reader: ${topic} has ${streamCounts[topic]} messages, expected ${n}`);
}
// 3. Data-section CRC: everything from the magic up to the Data End record (13 bytes before the summary).
offsetOfDataEnd = Number(reader.footer.summaryStart) - 13;
check(dataEnd !== undefined && dataEnd.dataSectionCrc === crc32(bytes.subarray(0, offsetOfDataEnd)), "data section CRC");

if (failures.length > 0) {
  console.error(`${file}: ${failures.length} interop failure(s):\n  ${failures.join("\n  ")}`);
  process.exit(1);
}
console.log(
  `${file}: @mcap/core reads ${topics.length} channels, ${expected.messages} messages, ` +
    `${reader.chunkIndexes.length} chunks (${[...compressions].map((c) => c || "none").join(", ")}): ok`,
);
