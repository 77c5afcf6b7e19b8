#!/bin/sh
# `handscan decode --device D` on a recording equals decoding the plain capture, except that each
# sample now carries the host time of the recorded message (non-zero).
# usage: decode_from_recording.sh HANDSCAN RECORDING_FROM_CAPTURE CAPTURE DEVICE TOPIC WORKDIR
set -eu
handscan=$1 convert=$2 capture=$3 device=$4 topic=$5 work=$6
if [ ! -f "$capture" ]; then
  echo "skipped: $capture not found (shared data absent)"
  exit 77
fi
rec=$work/decode_$device.mcap
"$convert" "$capture" "$topic" "$rec"
"$handscan" decode --device "$device" "$capture" | sed 's/"t_host_ns":[0-9]*//' > "$rec.plain.jsonl"
"$handscan" decode --device "$device" "$rec" > "$rec.jsonl"
sed 's/"t_host_ns":[0-9]*//' "$rec.jsonl" | diff -u "$rec.plain.jsonl" - 
if grep -q '"t_host_ns":0,' "$rec.jsonl"; then
  echo "FAIL: a sample decoded from the recording has no host time"
  exit 1
fi
lines=$(grep -c t_host_ns "$rec.jsonl")
[ "$lines" -gt 0 ] || { echo "FAIL: nothing decoded"; exit 1; }
echo "ok: $lines samples identical from $capture and from $rec, with host times"
