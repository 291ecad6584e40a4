// Tiller cockpit page: plain JavaScript, no library. Talks to tiller-cockpit over the WebSocket
// at /ws (docs/reference/cockpit-api.md): state frames in, commands (with the token) out.
'use strict';
const $ = (id) => document.getElementById(id);
const st = { msgs: {}, health: [], hello: null, track: [], t: 0, pilot: null, mission: null };
let ws = null;
let token = sessionStorage.getItem('tiller-token') || '';
let nextId = 1;
const TRACK_MAX = 3000;

(function takeTokenFromUrl() {
  const m = location.hash.match(/token=([^&]+)/);
  if (m) {
    token = decodeURIComponent(m[1]);
    sessionStorage.setItem('tiller-token', token);
    history.replaceState(null, '', location.pathname);  // the token leaves the address bar
  }
})();

function showToken() {
  const p = $('tokenstate');
  p.textContent = token ? 'commands: token set' : 'read only: no token';
  p.className = 'pill ' + (token ? 'ok' : 'warn');
}

function send(obj) {
  if (!ws || ws.readyState !== 1) return false;
  obj.token = token;
  ws.send(JSON.stringify(obj));
  return true;
}

function command(obj) {
  obj.id = nextId++;
  if (!send(obj)) showReply({ ok: false, command: obj.type, error: 'not connected' });
}

function showReply(r) {
  const el = $('reply');
  el.textContent = (r.ok ? 'ok: ' : 'refused: ') + (r.command || '') + ': ' + (r.ok ? r.detail : r.error);
  el.className = 'reply' + (r.ok ? '' : ' err');
}

function connect() {
  ws = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws');
  ws.onopen = () => { $('link').textContent = 'connected'; $('link').className = 'pill ok'; };
  ws.onclose = () => {
    $('link').textContent = 'link lost'; $('link').className = 'pill bad';
    padSending = false;
    setTimeout(connect, 1000);
  };
  ws.onmessage = (ev) => {
    const m = JSON.parse(ev.data);
    if (m.type === 'hello') { st.hello = m; return; }
    if (m.type === 'reply') { if (m.command !== 'gamepad' || !m.ok) showReply(m); return; }
    if (m.type === 'state' || m.type === 'snapshot') onState(m);
    if (m.type === 'mission') st.mission = m;  // the loaded plan: drawn under the path
  };
}

function onState(m) {
  st.t = m.t;
  for (const [ch, v] of Object.entries(m.msgs)) {
    st.msgs[ch] = v;
    if (ch === 'TILLER_ODOMETRY') {
      const o = v.msg;
      const last = st.track[st.track.length - 1];
      if (!last || Math.hypot(o.position[0] - last[0], o.position[1] - last[1]) > 0.05) {
        st.track.push([o.position[0], o.position[1]]);
        if (st.track.length > TRACK_MAX) st.track.shift();
      }
    }
  }
  st.health = m.health;
  st.pilot = m.pilot;
  st.cockpit = m.cockpit;
  samplePlots();
  if (!renderPending) { renderPending = true; requestAnimationFrame(() => { renderPending = false; render(); }); }
}
let renderPending = false;  // at most one render per animation frame, whatever the frame rate

// A canvas draws at its displayed size (CSS sets it), so nothing is stretched.
function fit(cv) {
  if (cv.width !== cv.clientWidth && cv.clientWidth > 0) cv.width = cv.clientWidth;
  if (cv.height !== cv.clientHeight && cv.clientHeight > 0) cv.height = cv.clientHeight;
}

const msg = (ch) => (st.msgs[ch] ? st.msgs[ch].msg : null);
const deg = (r) => { let d = (r * 180) / Math.PI; if (d < 0) d += 360; return d; };
const fmt = (x, n = 2) => (x === null || x === undefined || Number.isNaN(x) ? '-' : Number(x).toFixed(n));

function setpoint() {
  const s = msg('TILLER_VELOCITY_SETPOINT');
  if (!s || !s.active) return { speed: null, heading: null };
  return { speed: Math.hypot(s.velocity[0], s.velocity[1]), heading: s.heading_valid ? deg(s.target_heading) : null };
}

function pill(id, text, cls) { const p = $(id); p.textContent = text; p.className = 'pill ' + cls; }

function render() {
  const c = (st.hello && st.hello.constants) || {};
  const arm = msg('TILLER_ARM_STATE');
  pill('armed', arm ? (arm.armed ? 'ARMED' : 'disarmed') : 'arm ?', arm ? (arm.armed ? 'bad' : 'ok') : '');
  $('armreason').textContent = arm ? arm.reason : '-';
  $('controller').textContent = arm && arm.armed ? (arm.controller || '(no station named)') : '-';
  const g = msg('TILLER_GNSS');
  const fixes = ['no fix', '2D', '3D', 'DGPS', 'RTK float', 'RTK fixed', 'dead reckoning'];
  $('gnss').textContent = g ? fixes[g.fix_type] + ', ' + (g.satellites >= 0 ? g.satellites : '?') +
    ' satellites, HDOP ' + (g.hdop > 0 ? fmt(g.hdop, 1) : '?') + ', 1-sigma ' +
    (g.position_std[0] > 0 ? fmt(Math.max(g.position_std[0], g.position_std[1]), 2) + ' m' : 'unknown') : '-';
  const tc = msg('TILLER_THRUSTER_COMMAND');
  const gates = ['DISARMED', 'WAIT_NEUTRAL', 'ACTIVE', 'INPUT_LOST', 'TEST'];
  pill('gate', tc ? 'gate ' + gates[tc.gate] : 'gate ?', tc ? (tc.gate === 2 || tc.gate === 4 ? 'warn' : '') : '');
  $('hold').textContent = tc && tc.hold ? tc.hold : '-';
  const arb = msg('TILLER_ARBITRATION'), mode = msg('TILLER_MODE');
  const modes = ['MANUAL_OPEN_LOOP', 'MANUAL_CLOSED_LOOP', 'WAYPOINTING', 'STABILISE', 'DEPTH_HOLD',
    'HEADING_HOLD', 'RATE', 'SURFACE', 'POSITION_HOLD', 'DEPTH_HEADING_HOLD'];
  // The mode in force (the arbitration's) and, when it differs, the request and why it is not.
  const inForce = arb ? arb.mode : (mode ? mode.mode : null);
  const asked = mode && arb && mode.mode !== arb.mode ? ' (asked ' + modes[mode.mode] + ': ' + arb.reason + ')' : '';
  pill('mode', 'mode ' + (inForce === null ? '?' : modes[inForce]) + asked, asked ? 'warn' : '');
  const vs = msg('TILLER_VEHICLE_STATUS');
  pill('failsafe', vs ? (vs.active ? 'FAILSAFE: ' + vs.reason : 'no failsafe') : 'failsafes: no monitor', vs && vs.active ? 'bad' : '');
  const o = msg('TILLER_ODOMETRY');
  const sp = setpoint();
  if (o) {
    $('speed').textContent = fmt(Math.hypot(o.velocity[0], o.velocity[1])) + ' m/s';
    $('heading').textContent = fmt(deg(o.orientation[2]), 1) + ' deg';
    $('depth').textContent = fmt(o.position[2]) + ' m';
    $('attitude').textContent = fmt(deg(o.orientation[0]) > 180 ? deg(o.orientation[0]) - 360 : deg(o.orientation[0]), 1) + ' / ' +
      fmt((o.orientation[1] * 180) / Math.PI, 1) + ' deg';
    $('pos').textContent = fmt(o.position[0]) + ' / ' + fmt(o.position[1]) + ' m';
  }
  $('speed_sp').textContent = sp.speed === null ? '-' : fmt(sp.speed) + ' m/s';
  $('heading_sp').textContent = sp.heading === null ? '-' : fmt(sp.heading, 1) + ' deg';
  const pr = msg('TILLER_PATH_PROGRESS');
  if (pr) {
    $('xte').textContent = fmt(pr.cross_track_error) + ' m';
    $('progress').textContent = pr.path_id < 0 ? 'no path' :
      `point ${pr.segment + 1} of ${pr.n_waypoints}, ${fmt(pr.distance_to_goal, 1)} m to goal` + (pr.complete ? ', COMPLETE' : '') +
      (pr.skipped_waypoints ? `, ${pr.skipped_waypoints} skipped` : '');
  }
  renderThrusters(tc);
  renderHealth();
  renderPad();
  drawMap();
  drawAttitude();
  renderTest(tc);
  drawPlots();
}

function renderThrusters(tc) {
  const box = $('thrusters');
  const al = msg('TILLER_ALLOCATION_STATUS');
  if (!tc) { box.textContent = 'no thruster commands'; return; }
  if (box.children.length !== tc.n_thrusters) {
    box.innerHTML = '';
    for (let i = 0; i < tc.n_thrusters; i++) {
      const row = document.createElement('div');
      row.className = 'bar';
      row.innerHTML = `<span>${tc.names[i]}</span><div class="track"><div class="mid"></div><div class="fill"></div></div><span class="v"></span>`;
      box.appendChild(row);
    }
  }
  for (let i = 0; i < tc.n_thrusters; i++) {
    const row = box.children[i];
    const v = Math.max(-1, Math.min(1, tc.command[i]));
    const fill = row.querySelector('.fill');
    fill.style.left = (v >= 0 ? 50 : 50 + v * 50) + '%';
    fill.style.width = Math.abs(v) * 50 + '%';
    const sat = al && al.saturated && al.saturated[i];
    fill.className = 'fill' + (sat ? ' sat' : '');
    row.querySelector('.v').textContent = fmt(tc.command[i]) + (sat ? ' SAT' : '');
  }
  if (al) {
    const un = al.unallocated.map((x) => Math.abs(x)).reduce((a, b) => Math.max(a, b), 0);
    $('alloc').textContent = `${al.strategy}, scale ${fmt(al.scale)}, largest unmet ${fmt(un)}; limits -1..+1`;
  }
}

function renderHealth() {
  const t = $('health');
  t.innerHTML = '';
  for (const h of st.health) {
    const tr = document.createElement('tr');
    tr.className = h.state;
    tr.dataset.process = h.process;
    tr.innerHTML = `<td>${h.process}</td><td>${h.state}</td><td>${h.age_s === null ? '-' : fmt(h.age_s, 1) + ' s'}</td><td></td>`;
    tr.lastChild.textContent = h.status;
    t.appendChild(tr);
  }
  const c = st.cockpit;
  if (c) {
    const tr = document.createElement('tr');
    tr.className = 'OK';
    tr.innerHTML = `<td>cockpit</td><td>OK</td><td></td><td>commands accepted ${c.accepted}, refused without token ${c.token_refused}</td>`;
    tr.id = 'cockpit_counts';
    t.appendChild(tr);
  }
}

// ---- map: local NED, north up, east right
function drawMap() {
  const cv = $('map'); fit(cv); const g = cv.getContext('2d');
  const W = cv.width, H = cv.height;
  g.clearRect(0, 0, W, H);
  const path = msg('TILLER_PATH');
  const o = msg('TILLER_ODOMETRY');
  const pts = [];
  if (path) for (const w of path.waypoints) pts.push([w.position[0], w.position[1]]);
  const plan = st.mission;
  if (plan) {
    for (const p of plan.points) pts.push(p);
    for (const f of plan.fence) {
      if (f.circle) { pts.push([f.centre[0] - f.radius, f.centre[1] - f.radius], [f.centre[0] + f.radius, f.centre[1] + f.radius]); }
      else for (const v of f.polygon) pts.push(v);
    }
  }
  for (const p of st.track) pts.push(p);
  if (o) pts.push([o.position[0], o.position[1]]);
  if (!pts.length) { g.fillStyle = '#667'; g.fillText('no odometry yet', 10, 20); return; }
  let nmin = Infinity, nmax = -Infinity, emin = Infinity, emax = -Infinity;
  for (const [n, e] of pts) { nmin = Math.min(nmin, n); nmax = Math.max(nmax, n); emin = Math.min(emin, e); emax = Math.max(emax, e); }
  const span = Math.max(nmax - nmin, emax - emin, 10) * 1.15;
  const s = Math.min(W, H) / span;
  const cn = (nmin + nmax) / 2, ce = (emin + emax) / 2;
  const X = (e) => W / 2 + (e - ce) * s, Y = (n) => H / 2 - (n - cn) * s;
  // grid every 5 or 10 m
  const step = span > 60 ? 10 : 5;
  g.strokeStyle = '#1e2630'; g.lineWidth = 1;
  for (let e = Math.floor((ce - W / 2 / s) / step) * step; e < ce + W / 2 / s; e += step) { g.beginPath(); g.moveTo(X(e), 0); g.lineTo(X(e), H); g.stroke(); }
  for (let n = Math.floor((cn - H / 2 / s) / step) * step; n < cn + H / 2 / s; n += step) { g.beginPath(); g.moveTo(0, Y(n)); g.lineTo(W, Y(n)); g.stroke(); }
  g.fillStyle = '#556'; g.fillText(`grid ${step} m`, 6, H - 6);
  if (plan) drawPlan(g, plan, X, Y, s);
  const pr = msg('TILLER_PATH_PROGRESS');
  if (path && path.n_waypoints) {
    g.strokeStyle = '#c9a227'; g.setLineDash([6, 4]); g.beginPath();
    path.waypoints.forEach((w, i) => (i ? g.lineTo : g.moveTo).call(g, X(w.position[1]), Y(w.position[0])));
    g.stroke(); g.setLineDash([]);
    const sameId = pr && pr.path_id === path.path_id;
    path.waypoints.forEach((w, i) => {
      const reached = sameId && (pr.complete || i < pr.segment);
      g.fillStyle = reached ? '#3cb371' : '#c9a227';
      g.beginPath(); g.arc(X(w.position[1]), Y(w.position[0]), 5, 0, 2 * Math.PI); g.fill();
      g.fillStyle = '#ccd'; g.fillText(String(i + 1), X(w.position[1]) + 7, Y(w.position[0]) - 7);
    });
  }
  if (st.track.length > 1) {
    g.strokeStyle = '#4aa3ff'; g.lineWidth = 2; g.beginPath();
    st.track.forEach(([n, e], i) => (i ? g.lineTo : g.moveTo).call(g, X(e), Y(n)));
    g.stroke(); g.lineWidth = 1;
  }
  if (o) {
    const psi = o.orientation[2];
    const x = X(o.position[1]), y = Y(o.position[0]);
    g.save(); g.translate(x, y); g.rotate(psi);
    g.fillStyle = '#ffffff'; g.beginPath(); g.moveTo(0, -12); g.lineTo(7, 9); g.lineTo(-7, 9); g.closePath(); g.fill();
    g.restore();
  }
  $('mapinfo').textContent = (o ? `vehicle at N ${fmt(o.position[0], 1)} E ${fmt(o.position[1], 1)} m` : '') +
    (plan ? ` · plan ${plan.name}: ${plan.points.length} points, ${plan.fence.length} fence shapes` : '');
}

// The loaded plan (the cockpit's "mission" frame, local NED m): the fence (inclusion green,
// exclusion red), every item's point in order (grey, numbered), home (H) and rally points (R).
function drawPlan(g, plan, X, Y, s) {
  for (const f of plan.fence) {
    g.strokeStyle = f.inclusion ? '#3cb371' : '#e5534b'; g.lineWidth = 2;
    g.fillStyle = f.inclusion ? 'rgba(60,179,113,0.06)' : 'rgba(229,83,75,0.15)';
    g.beginPath();
    if (f.circle) g.arc(X(f.centre[1]), Y(f.centre[0]), f.radius * s, 0, 2 * Math.PI);
    else f.polygon.forEach(([n, e], i) => (i ? g.lineTo : g.moveTo).call(g, X(e), Y(n)));
    g.closePath(); g.fill(); g.stroke(); g.lineWidth = 1;
  }
  if (plan.points.length) {
    g.strokeStyle = '#6b7280'; g.beginPath();
    plan.points.forEach(([n, e], i) => (i ? g.lineTo : g.moveTo).call(g, X(e), Y(n)));
    g.stroke();
    g.fillStyle = '#9aa3ad';
    plan.points.forEach(([n, e], i) => g.fillText(String(i + 1), X(e) - 12, Y(n) + 14));
  }
  const mark = (p, letter, colour) => {
    g.fillStyle = colour; g.beginPath(); g.arc(X(p[1]), Y(p[0]), 7, 0, 2 * Math.PI); g.fill();
    g.fillStyle = '#111'; g.fillText(letter, X(p[1]) - 3, Y(p[0]) + 4);
  };
  if (plan.home) mark(plan.home, 'H', '#f0f0f0');
  for (const r of plan.rally) mark(r, 'R', '#a78bfa');
}

// ---- gamepad: the page is a pilot source; it sends its axes every period while visible
let padSending = false;
function renderPad() {
  const p = st.pilot;
  $('pilot').textContent = p ? (p.client < 0 ? 'no pilot' : (p.centred ? 'pilot in control, demand ' : 'pilot: centre the sticks, demand ') +
    p.demand.map((x) => fmt(x)).join(' ')) : '-';
}
function currentPad() {
  const pads = navigator.getGamepads ? navigator.getGamepads() : [];
  for (const p of pads) if (p && p.connected) return p;
  return null;
}
let lastTick = 0;
window.__maxTimerGap = 0;  // the longest gap between two ticks, ms (a starved browser shows here)
function padTick() {
  const nowMs = performance.now();
  if (lastTick) window.__maxTimerGap = Math.max(window.__maxTimerGap, nowMs - lastTick);
  lastTick = nowMs;
  const pad = currentPad();
  const visible = document.visibilityState === 'visible';
  const box = $('pad');
  if (pad) {
    $('padinfo').textContent = pad.id.slice(0, 40);
    box.innerHTML = Array.from(pad.axes).map((a, i) => `<div class="bar"><span>axis ${i}</span><div class="track"><div class="mid"></div>` +
      `<div class="fill" style="left:${a >= 0 ? 50 : 50 + a * 50}%;width:${Math.abs(a) * 50}%"></div></div><span>${fmt(a)}</span></div>`).join('');
  } else {
    $('padinfo').textContent = 'none (press a button on the gamepad)';
  }
  renderCalibration(pad);
  if (!token || !ws || ws.readyState !== 1) { padSending = false; return; }
  if (pad && visible) {
    send({ type: 'gamepad', connected: true, axes: Array.from(pad.axes) });
    padSending = true;
  } else if (padSending) {
    send({ type: 'gamepad', connected: false });
    padSending = false;
  }
}
function padLost() { if (padSending) { send({ type: 'gamepad', connected: false }); padSending = false; } }
document.addEventListener('visibilitychange', () => { if (document.visibilityState !== 'visible') padLost(); });
window.addEventListener('pagehide', padLost);
window.addEventListener('gamepaddisconnected', () => { if (!currentPad()) padLost(); });

// ---- controls
$('arm').onclick = () => {
  if (!window.confirm('Arm the thrusters? Thrust follows the source in control once it shows neutral.')) return;
  command({ type: 'arm', arm: true, confirm: true });
};
$('disarm').onclick = () => command({ type: 'arm', arm: false });
$('modebtn').onclick = () => command({ type: 'mode', mode: $('modesel').value });
for (const c of ['start', 'pause', 'resume', 'abort', 'release'])
  $(c).onclick = () => command({ type: 'mission', command: c });
$('tokenbtn').onclick = () => { token = $('token').value.trim(); sessionStorage.setItem('tiller-token', token); showToken(); };
function loadFile(f) { f.text().then((text) => command({ type: 'mission_load', name: f.name, text })); }
$('file').onchange = (e) => { if (e.target.files[0]) loadFile(e.target.files[0]); };
const drop = $('drop');
drop.ondragover = (e) => { e.preventDefault(); drop.classList.add('over'); };
drop.ondragleave = () => drop.classList.remove('over');
drop.ondrop = (e) => { e.preventDefault(); drop.classList.remove('over'); if (e.dataTransfer.files[0]) loadFile(e.dataTransfer.files[0]); };

// Start once every script of the page has run: plots.js and panels.js define what the ticks and
// the frames call, and a timer can fire while the parser still waits for them to load (seen in CI
// under load: "renderCalibration is not defined").
function start() {
  showToken();
  connect();
  setInterval(padTick, 50);
}
if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();
