// tiller-mavlink end to end, with node-mavlink as the ground station: against the real processes
// (config/launch/sim_usv_mavlink.yaml, started by ../mavlink_e2e_test.sh inside a private network
// namespace). Checks: a signed HEARTBEAT of a SURFACE_BOAT, the parameter list, an unsigned arm
// dropped, a second station refused, a signed arm, a 5-item mission up and down, MANUAL_CONTROL
// driving the thrusters (SERVO_OUTPUT_RAW off 1500 us), a malformed-frame fuzz with the bridge
// alive and every output neutral, a disarm. Prints one line per check; exit 1 on a failure.
// Args: SECRET_HEX
'use strict';
const dgram = require('dgram');
const { PassThrough } = require('stream');
const {
  MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common,
} = require('node-mavlink');

const VEHICLE = { address: '127.0.0.1', port: 14551 };
const key = Buffer.from(process.argv[2], 'hex');
const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };
const sock = dgram.createSocket('udp4');
const packets = [];  // {t, msgid, data, signed}
const stream = new PassThrough();
stream.pipe(new MavLinkPacketSplitter()).pipe(new MavLinkPacketParser()).on('data', (p) => {
  const clazz = REGISTRY[p.header.msgid];
  if (!clazz) return;
  packets.push({ t: Date.now(), msgid: p.header.msgid, data: p.protocol.data(p.payload, clazz),
                 signed: p.signature !== null });
});
sock.on('message', (m) => stream.write(m));

let failed = 0;
let passed = 0;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (ok) passed += 1; else failed += 1;
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
async function waitFor(pred, ms) {
  const end = Date.now() + ms;
  for (;;) {
    const p = packets.find(pred);
    if (p) return p;
    if (Date.now() > end) return null;
    await sleep(20);
  }
}
const seqs = {};
let lastTs = 0;
function frame(msg, { sysid = 255, signed = true } = {}) {
  const proto = new MavLinkProtocolV2(sysid, 190, signed ? MavLinkProtocolV2.IFLAG_SIGNED : 0);
  seqs[sysid] = ((seqs[sysid] || 0) + 1) & 255;
  let b = proto.serialize(msg, seqs[sysid]);
  if (signed) {
    lastTs = Math.max(Date.now(), lastTs + 1);  // strictly increasing per stream
    b = proto.sign(b, 0, key, lastTs);
  }
  return b;
}
function send(msg, opts) {
  sock.send(frame(msg, opts), VEHICLE.port, VEHICLE.address);
}
function command(cmd, p1, opts) {
  const c = new common.CommandLong();
  c.targetSystem = 1; c.targetComponent = 1; c.command = cmd; c.confirmation = 0;
  c._param1 = p1; c._param2 = 0; c._param3 = 0; c._param4 = 0; c._param5 = 0; c._param6 = 0;
  c._param7 = 0;
  send(c, opts);
}
function manual(x, r) {
  const m = new common.ManualControl();
  m.target = 1; m.x = x; m.y = 0; m.z = 500; m.r = r; m.buttons = 0;
  send(m);
}
const armed = (p) => p.msgid === minimal.Heartbeat.MSG_ID &&
  (p.data.baseMode & minimal.MavModeFlag.SAFETY_ARMED) !== 0;
const since = (t, pred) => (p) => p.t >= t && pred(p);

async function main() {
  await new Promise((r) => sock.bind(14550, '127.0.0.1', r));
  const hb = await waitFor((p) => p.msgid === minimal.Heartbeat.MSG_ID, 20000);
  check(hb && hb.data.type === minimal.MavType.SURFACE_BOAT &&
        hb.data.autopilot === minimal.MavAutopilot.GENERIC && hb.signed,
        'signed HEARTBEAT: SURFACE_BOAT, autopilot GENERIC');
  if (!hb) process.exit(1);
  // The station's heartbeat (QGroundControl sends one every second).
  const gcsHb = () => {
    const h = new minimal.Heartbeat();
    h.type = minimal.MavType.GCS; h.autopilot = minimal.MavAutopilot.INVALID; h.baseMode = 0;
    h.customMode = 0; h.systemStatus = minimal.MavState.ACTIVE; h.mavlinkVersion = 3;
    send(h);
  };
  const hbTimer = setInterval(gcsHb, 1000);
  gcsHb();

  let t = Date.now();
  const pl = new common.ParamRequestList();
  pl.targetSystem = 1; pl.targetComponent = 1;
  send(pl);
  await sleep(500);
  const params = packets.filter(since(t, (p) => p.msgid === common.ParamValue.MSG_ID));
  check(params.length >= 5 && params.some((p) => p.data.paramId === 'MAN_GAIN'),
        `parameter list: ${params.map((p) => p.data.paramId).join(', ')}`);
  const kerr = params.find((p) => p.data.paramId === 'VP_SURGE_KERR');
  check(params.length === 40 && kerr !== undefined && kerr.data.paramValue === 150,
        `the controllers' gains listed: ${params.length} parameters, VP_SURGE_KERR ` +
        `${kerr ? kerr.data.paramValue : 'missing'} (config/control/otter.yaml: 150)`);

  // Wait for the stack: odometry through (GLOBAL_POSITION_INT) before arming.
  await waitFor((p) => p.msgid === common.GlobalPositionInt.MSG_ID, 15000);

  t = Date.now();
  command(common.MavCmd.COMPONENT_ARM_DISARM, 1, { signed: false });
  await sleep(1500);
  check(!packets.some(since(t, armed)) &&
        !packets.some(since(t, (p) => p.msgid === common.CommandAck.MSG_ID)),
        'an unsigned arm is dropped: no ACK, still disarmed');

  t = Date.now();
  command(common.MavCmd.COMPONENT_ARM_DISARM, 1, { sysid: 254 });
  const denied = await waitFor(since(t, (p) => p.msgid === common.CommandAck.MSG_ID), 2000);
  await sleep(800);
  check(denied && denied.data.result === common.MavResult.DENIED && !packets.some(since(t, armed)),
        'a second station (system 254, signed) is refused: DENIED, still disarmed');

  t = Date.now();
  manual(0, 0);  // centred first, as a real stick at rest
  command(common.MavCmd.COMPONENT_ARM_DISARM, 1);
  const ack = await waitFor(since(t, (p) => p.msgid === common.CommandAck.MSG_ID), 2000);
  const arm = await waitFor(since(t, armed), 3000);
  check(ack && ack.data.result === common.MavResult.ACCEPTED && arm, 'signed arm: ACCEPTED, armed');

  // A 5-item mission up and down.
  const items = [];
  for (let i = 0; i < 5; i += 1) {
    const it = new common.MissionItemInt();
    it.targetSystem = 1; it.targetComponent = 1; it.seq = i;
    it.frame = common.MavFrame.GLOBAL_RELATIVE_ALT_INT; it.command = common.MavCmd.NAV_WAYPOINT;
    it.current = 0; it.autocontinue = 1; it.param1 = 0; it.param2 = 1; it.param3 = 0;
    it.param4 = 0; it.x = 0; it.z = 0; it.missionType = 0;
    items.push(it);
  }
  const gp = packets.filter((p) => p.msgid === common.GlobalPositionInt.MSG_ID).pop();
  items.forEach((it, i) => { it.x = gp.data.lat + (i + 1) * 900; it.y = gp.data.lon + i * 900; });
  t = Date.now();
  const count = new common.MissionCount();
  count.targetSystem = 1; count.targetComponent = 1; count.count = 5; count.missionType = 0;
  count.opaqueId = 0;
  send(count);
  let served = 0;
  const end = Date.now() + 5000;
  let result = null;
  while (Date.now() < end && result === null) {
    const req = packets.find(since(t, (p) => p.msgid === common.MissionRequestInt.MSG_ID &&
                                             !p.done));
    if (req) { req.done = true; send(items[req.data.seq]); served += 1; }
    const a = packets.find(since(t, (p) => p.msgid === common.MissionAck.MSG_ID));
    if (a) result = a.data.type;
    await sleep(10);
  }
  check(result === common.MavMissionResult.ACCEPTED && served === 5,
        `mission upload: 5 items requested and ACCEPTED (result ${result})`);
  t = Date.now();
  const rl = new common.MissionRequestList();
  rl.targetSystem = 1; rl.targetComponent = 1; rl.missionType = 0;
  send(rl);
  const cnt = await waitFor(since(t, (p) => p.msgid === common.MissionCount.MSG_ID), 2000);
  const down = [];
  for (let i = 0; cnt && i < cnt.data.count; i += 1) {
    const tt = Date.now();
    const r = new common.MissionRequestInt();
    r.targetSystem = 1; r.targetComponent = 1; r.seq = i; r.missionType = 0;
    send(r);
    const it = await waitFor(since(tt, (p) => p.msgid === common.MissionItemInt.MSG_ID &&
                                              p.data.seq === i), 2000);
    if (it) down.push(it.data);
  }
  const same = down.length === 5 && down.every((d, i) => d.x === items[i].x && d.y === items[i].y &&
                                                        d.command === items[i].command);
  check(same, `mission download: ${down.length} items, the same as uploaded`);

  // Drive: the stick ahead for 3 s at 20 Hz.
  t = Date.now();
  for (let i = 0; i < 60; i += 1) { manual(i < 4 ? 0 : 700, 0); await sleep(50); }
  const driven = packets.filter(since(t, (p) => p.msgid === common.ServoOutputRaw.MSG_ID &&
                                               Math.abs(p.data.servo1Raw - 1500) > 20));
  const speed = packets.filter(since(t, (p) => p.msgid === common.VfrHud.MSG_ID)).pop();
  check(driven.length > 0 && speed && speed.data.groundspeed > 0.1,
        `MANUAL_CONTROL drives: ${driven.length} SERVO_OUTPUT_RAW off neutral, ` +
        `${speed ? speed.data.groundspeed.toFixed(2) : '?'} m/s`);
  manual(0, 0);
  await sleep(1500);  // the stick released, then silent: neutral

  // Fuzz: 3000 malformed datagrams (random bytes, flipped bytes of good frames, truncations).
  const good = frame(Object.assign(new common.ManualControl(),
    { target: 1, x: 900, y: 0, z: 500, r: 900, buttons: 0 }));
  let seed = 12345;
  const rnd = () => { seed = (seed * 1103515245 + 12345) & 0x7fffffff; return seed; };
  t = Date.now();
  for (let i = 0; i < 3000; i += 1) {
    let b;
    if (i % 3 === 0) {
      b = Buffer.alloc(1 + (rnd() % 290)); for (let k = 0; k < b.length; k += 1) b[k] = rnd() & 255;
      b[0] = 0xfd;
    } else if (i % 3 === 1) {
      b = Buffer.from(good); b[rnd() % b.length] ^= 1 + (rnd() % 255);
    } else {
      b = Buffer.from(good).subarray(0, rnd() % good.length);
    }
    sock.send(b, VEHICLE.port, VEHICLE.address);
    if (i % 100 === 99) await sleep(10);
  }
  await sleep(1500);
  const offNeutral = packets.filter(since(t, (p) => p.msgid === common.ServoOutputRaw.MSG_ID &&
                                                   Math.abs(p.data.servo1Raw - 1500) > 2));
  const alive = packets.some(since(Date.now() - 1200, (p) => p.msgid === minimal.Heartbeat.MSG_ID));
  check(alive && offNeutral.length === 0,
        `malformed-frame fuzz: the bridge alive, ${offNeutral.length} outputs off neutral`);

  t = Date.now();
  command(common.MavCmd.COMPONENT_ARM_DISARM, 0);
  const disarmed = await waitFor(since(t + 100, (p) => p.msgid === minimal.Heartbeat.MSG_ID &&
                                                       !armed(p)), 3000);
  check(disarmed, 'disarm');
  const texts = packets.filter((p) => p.msgid === common.StatusText.MSG_ID).map((p) => p.data.text);
  console.log(`STATUSTEXT seen: ${JSON.stringify(texts)}`);
  clearInterval(hbTimer);
  sock.close();
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}
main().catch((e) => { console.log(`FAIL ${e.stack}`); process.exit(1); });
