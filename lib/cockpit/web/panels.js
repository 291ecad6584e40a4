// Tiller cockpit page: the attitude view (ROV), the gamepad calibration view and the thruster
// test. Loaded after cockpit.js (uses its st, $, msg, fmt, command, send).
'use strict';

// ---- attitude: an artificial horizon (roll, pitch), a heading ring (yaw) and a depth bar
function drawAttitude() {
  const cv = $('attitude_cv'); fit(cv);
  const g = cv.getContext('2d'), W = cv.width, H = cv.height;
  g.clearRect(0, 0, W, H);
  const o = msg('TILLER_ODOMETRY');
  if (!o) { g.fillStyle = '#667'; g.fillText('no odometry yet', 10, 20); return; }
  const roll = o.orientation[0], pitch = o.orientation[1], yaw = o.orientation[2], depth = o.position[2];
  const R = Math.min(H / 2 - 8, W / 5), cx = R + 10, cy = H / 2;
  // Horizon: sky above, water below, rotated by -roll, moved down by +pitch (nose up).
  g.save(); g.beginPath(); g.arc(cx, cy, R, 0, 2 * Math.PI); g.clip();
  g.translate(cx, cy); g.rotate(-roll);
  const py = (pitch * 180 / Math.PI) * (R / 45);  // 45 deg of pitch = the radius
  g.fillStyle = '#2f5f8f'; g.fillRect(-2 * R, -3 * R + py, 4 * R, 3 * R);
  g.fillStyle = '#5a4327'; g.fillRect(-2 * R, py, 4 * R, 3 * R);
  g.strokeStyle = '#e6edf3'; g.lineWidth = 1;
  for (let d = -40; d <= 40; d += 10) {
    if (!d) continue;
    const y = py - d * (R / 45), w = d % 20 ? R * 0.18 : R * 0.32;
    g.beginPath(); g.moveTo(-w, y); g.lineTo(w, y); g.stroke();
    g.fillStyle = '#e6edf3'; g.fillText(String(d), w + 3, y + 4);
  }
  g.lineWidth = 2; g.beginPath(); g.moveTo(-2 * R, py); g.lineTo(2 * R, py); g.stroke();
  g.restore();
  g.strokeStyle = '#ffcc33'; g.lineWidth = 3; g.beginPath();
  g.moveTo(cx - R * 0.5, cy); g.lineTo(cx - R * 0.15, cy); g.lineTo(cx, cy + R * 0.1); g.lineTo(cx + R * 0.15, cy); g.lineTo(cx + R * 0.5, cy);
  g.stroke(); g.lineWidth = 1;
  g.strokeStyle = '#556'; g.beginPath(); g.arc(cx, cy, R, 0, 2 * Math.PI); g.stroke();
  // Heading ring: north up, the bow's direction as a needle.
  const hr = R * 0.7, hx = cx + R + 24 + hr;
  g.strokeStyle = '#556'; g.beginPath(); g.arc(hx, cy, hr, 0, 2 * Math.PI); g.stroke();
  g.fillStyle = '#9fb3c8';
  [['N', 0], ['E', 90], ['S', 180], ['W', 270]].forEach(([l, a]) => {
    const r = (a * Math.PI) / 180; g.fillText(l, hx + Math.sin(r) * (hr + 9) - 3, cy - Math.cos(r) * (hr + 9) + 4);
  });
  g.strokeStyle = '#ffffff'; g.lineWidth = 3; g.beginPath(); g.moveTo(hx, cy);
  g.lineTo(hx + Math.sin(yaw) * hr, cy - Math.cos(yaw) * hr); g.stroke(); g.lineWidth = 1;
  // Depth bar: 0 at the top, the larger of 10 m and the depth at the bottom.
  const dx = W - 40, dmax = Math.max(10, Math.ceil(depth / 10) * 10), top = 14, bot = H - 14;
  g.fillStyle = '#0e1a26'; g.fillRect(dx, top, 16, bot - top);
  g.fillStyle = '#4aa3ff'; g.fillRect(dx, top, 16, Math.max(0, Math.min(1, depth / dmax)) * (bot - top));
  g.fillStyle = '#778'; g.fillText('0', dx + 20, top + 4); g.fillText(String(dmax), dx + 20, bot);
  const d360 = (r) => { let d = (r * 180) / Math.PI; return d; };
  $('att_text').textContent = `roll ${fmt(d360(roll), 1)} deg, pitch ${fmt(d360(pitch), 1)} deg, ` +
    `yaw ${fmt(deg(yaw), 1)} deg, depth ${fmt(depth, 2)} m`;
}

// ---- gamepad calibration: every mapped axis raw and shaped (deadzone, expo as tiller-teleop's
// shape_axis), and the curve of one axis with deadzone and expo to try before writing a preset.
const shapeAxis = (x, dz, expo) => {
  const a = Math.abs(x);
  if (!(a > dz)) return 0;
  const s = Math.min((a - dz) / (1 - dz), 1), y = (1 - expo) * s + expo * s * s * s;
  return x < 0 ? -y : y;
};
let calAxes = null;  // the hello's mapping, copied (deadzone and expo editable here)
function calSetup() {
  if (calAxes || !st.hello) return;
  calAxes = st.hello.gamepad.axes.map((a) => Object.assign({}, a));
  const sel = $('cal_axis');
  calAxes.forEach((a, i) => { const op = document.createElement('option'); op.value = i; op.textContent = `axis ${a.axis} -> ${a.dof}`; sel.appendChild(op); });
  sel.onchange = calPick;
  $('cal_dz').oninput = $('cal_expo').oninput = () => {
    const a = calAxes[Number(sel.value)];
    a.deadzone = Math.max(0, Math.min(0.9, Number($('cal_dz').value)));
    a.expo = Math.max(0, Math.min(1, Number($('cal_expo').value)));
  };
  calPick();
}
function calPick() {
  const a = calAxes[Number($('cal_axis').value)];
  $('cal_dz').value = a.deadzone; $('cal_expo').value = a.expo;
}
function renderCalibration(pad) {
  calSetup();
  if (!calAxes) return;
  const rows = $('cal_rows');
  if (rows.children.length !== calAxes.length) {
    rows.innerHTML = '';
    for (const a of calAxes) {
      const r = document.createElement('div'); r.className = 'bar cal';
      r.innerHTML = `<span>${a.dof} (axis ${a.axis})</span><div class="track"><div class="mid"></div><div class="fill raw"></div></div>` +
        `<div class="track"><div class="mid"></div><div class="fill"></div></div><span class="v"></span>`;
      rows.appendChild(r);
    }
  }
  const bar = (el, v) => { el.style.left = (v >= 0 ? 50 : 50 + v * 50) + '%'; el.style.width = Math.abs(v) * 50 + '%'; };
  calAxes.forEach((a, i) => {
    const raw = pad && a.axis < pad.axes.length ? pad.axes[a.axis] : 0;
    const out = a.sign * shapeAxis(raw, a.deadzone, a.expo) * a.gain;
    const r = rows.children[i];
    bar(r.querySelector('.fill.raw'), raw); bar(r.querySelector('.track:nth-of-type(2) .fill'), out);
    r.querySelector('.v').textContent = `${fmt(raw)} -> ${fmt(out)}`;
  });
  // The curve of the chosen axis: output against raw input, the deadzone shaded, the stick a dot.
  const a = calAxes[Number($('cal_axis').value)];
  const cv = $('cal_curve'); fit(cv);
  const g = cv.getContext('2d'), W = cv.width, H = cv.height, s = Math.min(W, H) / 2 - 6, cx = W / 2, cy = H / 2;
  g.clearRect(0, 0, W, H);
  g.fillStyle = '#2a2f1a'; g.fillRect(cx - a.deadzone * s, cy - s, 2 * a.deadzone * s, 2 * s);
  g.strokeStyle = '#334'; g.strokeRect(cx - s, cy - s, 2 * s, 2 * s);
  g.beginPath(); g.moveTo(cx - s, cy); g.lineTo(cx + s, cy); g.moveTo(cx, cy - s); g.lineTo(cx, cy + s); g.stroke();
  g.strokeStyle = '#556'; g.setLineDash([3, 3]); g.beginPath(); g.moveTo(cx - s, cy + s); g.lineTo(cx + s, cy - s); g.stroke(); g.setLineDash([]);
  g.strokeStyle = '#4aa3ff'; g.lineWidth = 2; g.beginPath();
  for (let k = 0; k <= 100; k++) { const x = -1 + k / 50, y = shapeAxis(x, a.deadzone, a.expo); (k ? g.lineTo : g.moveTo).call(g, cx + x * s, cy - y * s); }
  g.stroke(); g.lineWidth = 1;
  const raw = pad && a.axis < pad.axes.length ? pad.axes[a.axis] : 0;
  g.fillStyle = '#ffcc33'; g.beginPath(); g.arc(cx + raw * s, cy - shapeAxis(raw, a.deadzone, a.expo) * s, 4, 0, 2 * Math.PI); g.fill();
  $('cal_yaml').textContent = `- {axis: ${a.axis}, dof: ${a.dof}, sign: ${a.sign}, deadzone: ${fmt(a.deadzone)}, expo: ${fmt(a.expo)}}`;
}

// ---- thruster test: pick a thruster, enable (the page asks first), hold the button to spin it.
// While held the page repeats the request every 0.1 s; letting go, leaving the button, losing the
// focus or hiding the page ends it at once (and tiller-cockpit, tiller-mixer end it on silence).
let testPress = 0, testTimer = null, testHeld = false;
const testMsg = (active) => ({ type: 'thruster_test', press: testPress, active, thruster: Number($('test_thruster').value),
  command: Number($('test_cmd').value), confirm: $('test_enable').checked });
function testDown(e) {
  if (!$('test_enable').checked || testHeld) return;
  if (e) { e.preventDefault(); try { spin.setPointerCapture(e.pointerId); } catch (x) { /* no capture */ } }
  testHeld = true; testPress++;
  command(testMsg(true));
  testTimer = setInterval(() => send(testMsg(true)), 100);
}
function testUp() {
  if (!testHeld) return;
  testHeld = false; clearInterval(testTimer); testTimer = null;
  send(testMsg(false));
}
const spin = $('test_spin');
spin.addEventListener('pointerdown', testDown);
for (const ev of ['pointerup', 'pointerleave', 'pointercancel', 'lostpointercapture']) spin.addEventListener(ev, testUp);
// A release anywhere ends it too (the page may have moved under a held pointer).
for (const ev of ['pointerup', 'mouseup', 'touchend', 'blur']) window.addEventListener(ev, testUp);
document.addEventListener('visibilitychange', () => { if (document.visibilityState !== 'visible') testUp(); });
$('test_enable').onchange = (e) => {
  if (e.target.checked && !window.confirm('Thruster test: the chosen thruster spins while the button is held ' +
      '(armed, with the pilot centred or no mission running, no failsafe active). Are the propellers clear?')) e.target.checked = false;
  if (!e.target.checked) testUp();
  spin.disabled = !e.target.checked;
};
function renderTest(tc) {
  const sel = $('test_thruster');
  if (tc && sel.options.length !== tc.n_thrusters) {
    sel.innerHTML = '';
    tc.names.forEach((n, i) => { const op = document.createElement('option'); op.value = i; op.textContent = `${i}: ${n}`; sel.appendChild(op); });
  }
  const cap = st.hello && st.hello.thruster_test ? st.hello.thruster_test.max_command : 0.1;
  const inp = $('test_cmd');
  if (inp.max !== String(cap)) { inp.max = cap; inp.min = -cap; if (Math.abs(Number(inp.value)) > cap) inp.value = cap; }
  const esc = msg('TILLER_ESC_OUTPUT'), i = Number(sel.value);
  const escText = esc && i < esc.n_channels ? `ESC ${esc.names[i]}: ${esc.value[i]} (${fmt(esc.normalized[i])})` : 'ESC: -';
  const gate = tc ? ['DISARMED', 'WAIT_NEUTRAL', 'ACTIVE', 'INPUT_LOST', 'TEST'][tc.gate] : '?';
  $('test_state').textContent = `gate ${gate}; ${escText}`;
  $('test_state').className = 'small' + (tc && tc.gate === 4 ? ' testing' : '');
  $('test_cap').textContent = `|command| <= ${cap}`;
}
