// The frame the server sends (and svr render --html embeds): "SVRI", uint32 n, n bytes of JSON,
// then the half-float planes.
"use strict";

function parseFrame(buffer) {
  const bytes = new Uint8Array(buffer);
  if (bytes.length < 8 || String.fromCharCode(...bytes.subarray(0, 4)) !== "SVRI")
    throw new Error("not an svr frame");
  const n = new DataView(buffer).getUint32(4, true);
  const header = JSON.parse(new TextDecoder().decode(bytes.subarray(8, 8 + n)));
  const planes = header.channels + header.t_channels;
  const count = planes * header.width * header.height;
  const half = header.samples === "half";
  if (8 + n + (half ? 2 : 4) * count > buffer.byteLength) throw new Error("frame is truncated");
  return {...header, planes, data: half ? new Uint16Array(buffer, 8 + n, count) : new Float32Array(buffer, 8 + n, count)};
}

function base64ToBuffer(text) {
  const s = atob(text), out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out.buffer;
}
