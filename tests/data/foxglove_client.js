// A Foxglove WebSocket client made only of Foxglove's npm packages, as a Foxglove user's tools are:
// @foxglove/ws-protocol (the protocol), @foxglove/rosmsg (parses the advertised ros2msg schema),
// @foxglove/rosmsg2-serialization (decodes CDR with it), ws (the socket).
//
//   node foxglove_client.js '<plan JSON>'
//
// plan: {url, subscribe: [topics], count, timeoutMs, malformed, publish: {topic, schemaName, message,
// times}, call: {service, request}, getParameters: [names], setParameters: [{name, value}],
// subscribeParameters: [names], graph,
// until: [event names], untilStatus, stamps}. Prints one JSON line per event: {"event": "message", "topic",
// "schemaName", "encoding", "message"}, {"event": "status", ...}, {"event": "response", ...};
// exits 0 once `count` messages of every subscribed topic, the call's response and one event of
// each name in `until` ("advertise", "unadvertise", "parameters", "graph", "time", and
// "statusMatch": a status containing `untilStatus`) arrived, 2 on timeout. With `stamps`
// (benchmarks/foxglove_bridge.py) it prints, for every message until timeoutMs, {"event": "stamp",
// "topic", "recvNs", "stampNs"} (receive time, header.stamp; wall clock) and exits 0 at timeoutMs.
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const { parse } = require("@foxglove/rosmsg");
const { MessageReader, MessageWriter } = require("@foxglove/rosmsg2-serialization");
const WebSocket = require("ws");

const plan = JSON.parse(process.argv[2]);
const count = plan.count ?? 1;
const wanted = new Set(plan.subscribe ?? []);
const received = new Map();
let callDone = !plan.call;

function summary(key, value) {
  if (typeof value === "bigint") return Number(value);
  if (ArrayBuffer.isView(value)) return { length: value.length, head: Array.from(value.slice(0, 8)) };
  return value;
}
const seen = new Set();
function emit(event) {
  process.stdout.write(JSON.stringify(event, summary) + "\n");
  seen.add(event.event);
  if (event.event !== "message" && event.event !== "response") finishIfDone();
}
function finishIfDone() {
  const topicsDone = [...wanted].every((t) => (received.get(t) ?? 0) >= count);
  const waits = !plan.stamps && (wanted.size > 0 || plan.call || (plan.until ?? []).length > 0); // else: until timeoutMs
  if (waits && topicsDone && callDone && (plan.until ?? []).every((name) => seen.has(name))) {
    client.close();
    process.exit(0);
  }
}
setTimeout(() => {
  emit({ event: "timeout", received: Object.fromEntries(received) });
  process.exit(plan.stamps ? 0 : 2);
}, plan.timeoutMs ?? 20000);

// The SDK server speaks `foxglove.sdk.v1` (the same protocol renamed); offering both, as Foxglove and
// Lichtblick do, connects to it and to older servers.
const ws = new WebSocket(plan.url, ["foxglove.sdk.v1", FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const readers = new Map(); // subscription id -> {topic, reader, schemaName, encoding}
const subscribed = new Set();

client.on("error", (error) => emit({ event: "error", text: String(error) }));
client.on("status", (status) => {
  if (plan.untilStatus && status.message.includes(plan.untilStatus)) seen.add("statusMatch");
  emit({ event: "status", level: status.level, text: status.message });
  // foxglove-sdk 0.30 queues an advertisement before it records the channel, so a subscription
  // sent at once can be refused as unknown (docs/web-tools.md); subscribe again, as a user would.
  const refused = /Unknown channel ID: (\d+)/.exec(status.message);
  const channel = refused && advertised.get(Number(refused[1]));
  if (channel) setTimeout(() => subscribeTo(channel), 100);
});
client.on("open", () => {
  if (plan.malformed) {
    ws.send("{this is not json");
    ws.send(JSON.stringify({ op: "noSuchOp" }));
    ws.send(Buffer.from([0xff, 0x00, 0x01]));
    ws.send(JSON.stringify({ op: "subscribe", subscriptions: "not a list" }));
  }
  if (plan.getParameters) client.getParameters(plan.getParameters, "get");
  if (plan.subscribeParameters) client.subscribeParameterUpdates(plan.subscribeParameters);
  if (plan.setParameters) client.setParameters(plan.setParameters, "set");
  if (plan.graph) client.subscribeConnectionGraph();
  if (plan.publish) {
    const p = plan.publish;
    const channelId = client.advertise({ topic: p.topic, encoding: "cdr", schemaName: p.schemaName });
    const writer = new MessageWriter(parse(p.schema, { ros2: true }));
    let sent = 0;
    const timer = setInterval(() => {
      client.sendMessage(channelId, writer.writeMessage(p.message));
      if (++sent >= (p.times ?? 20)) clearInterval(timer);
    }, 100);
  }
});
client.on("parameterValues", (values) => emit({ event: "parameters", id: values.id, parameters: values.parameters }));
client.on("connectionGraphUpdate", (update) => emit({ event: "graph", update }));
client.on("time", ({ timestamp }) => emit({ event: "time", timestamp: timestamp.toString() }));
client.on("unadvertise", (ids) => emit({ event: "unadvertise", channelIds: ids }));
const advertised = new Map(); // channel id -> channel we subscribed to
function subscribeTo(channel) {
  const reader = new MessageReader(parse(channel.schema, { ros2: true }));
  const id = client.subscribe(channel.id);
  readers.set(id, { topic: channel.topic, reader, schemaName: channel.schemaName, encoding: channel.encoding });
}
client.on("advertise", (channels) => {
  emit({ event: "advertise", channels: channels.map((c) => ({ id: c.id, topic: c.topic })) });
  for (const channel of channels) {
    if (!wanted.has(channel.topic) || subscribed.has(channel.topic)) continue;
    subscribed.add(channel.topic);
    advertised.set(channel.id, channel);
    subscribeTo(channel);
  }
});
client.on("advertiseServices", (services) => {
  if (!plan.call) return;
  const service = services.find((s) => s.name === plan.call.service);
  if (!service) return;
  const writer = new MessageWriter(parse(service.requestSchema ?? service.request.schema, { ros2: true }));
  const reader = new MessageReader(parse(service.responseSchema ?? service.response.schema, { ros2: true }));
  client.on("serviceCallResponse", (response) => {
    emit({ event: "response", service: plan.call.service, message: reader.readMessage(response.data) });
    callDone = true;
    finishIfDone();
  });
  client.on("serviceCallFailure", (failure) => emit({ event: "callFailure", text: failure.message }));
  client.sendServiceCallRequest({
    serviceId: service.id, callId: 1, encoding: "cdr", data: new DataView(writer.writeMessage(plan.call.request).buffer),
  });
});
client.on("message", ({ subscriptionId, data }) => {
  const entry = readers.get(subscriptionId);
  if (!entry) return;
  const message = entry.reader.readMessage(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
  received.set(entry.topic, (received.get(entry.topic) ?? 0) + 1);
  if (plan.stamps) {
    const recvNs = Math.round((performance.timeOrigin + performance.now()) * 1e6);
    const { sec, nanosec } = message.header.stamp;
    emit({ event: "stamp", topic: entry.topic, recvNs, stampNs: sec * 1e9 + nanosec });
    return;
  }
  if (received.get(entry.topic) <= count) {
    emit({ event: "message", topic: entry.topic, schemaName: entry.schemaName, encoding: entry.encoding, message });
  }
  finishIfDone();
});
