// Tiller cockpit page: live plots of the last minutes (plain canvas, no library). Samples go
// into fixed ring buffers (Float64Array, allocated once), so the page's memory does not grow
// with the run: PLOT_HZ samples a second for PLOT_MAX_S seconds, NaN where a value is absent.
'use strict';
const PLOT_HZ = 5, PLOT_MAX_S = 600;

class Ring {
  constructor(n, columns) {
    this.n = n; this.len = 0; this.head = 0;
    this.t = new Float64Array(n);
    this.cols = {};
    for (const c of columns) this.cols[c] = new Float64Array(n);
  }
  push(t, values) {
    this.t[this.head] = t;
    for (const c in this.cols) { const v = values[c]; this.cols[c][this.head] = v === null || v === undefined ? NaN : v; }
    this.head = (this.head + 1) % this.n;
    if (this.len < this.n) this.len++;
  }
  index(k) { return (this.head - this.len + k + this.n) % this.n; }  // k-th oldest
  last() { return this.len ? this.t[this.index(this.len - 1)] : NaN; }
}

const plotRing = new Ring(PLOT_HZ * PLOT_MAX_S, ['speed', 'speed_sp', 'heading', 'heading_sp', 'xte',
  'pid_p', 'pid_i', 'pid_d', 'pid_ff', 'pid_out']);
let plotLastSample = -Infinity, plotLastDraw = 0;
const plotValues = {};  // reused: one object for every sample

function samplePlots() {
  const t = st.t / 1e6;
  if (t - plotLastSample < 1 / PLOT_HZ) return;
  plotLastSample = t;
  const o = msg('TILLER_ODOMETRY');
  const sp = setpoint();
  const v = plotValues;
  v.speed = o ? Math.hypot(o.velocity[0], o.velocity[1]) : null;
  v.heading = o ? deg(o.orientation[2]) : null;
  v.speed_sp = sp.speed; v.heading_sp = sp.heading;
  const pr = msg('TILLER_PATH_PROGRESS');
  v.xte = pr && pr.path_id >= 0 ? pr.cross_track_error : null;
  const ch = $('pid_sel').value.split(':');
  const pid = msg(ch[0]);
  const ax = Number(ch[1]);
  const fresh = pid && st.msgs[ch[0]].rx > st.t - 1e6;
  v.pid_p = fresh ? pid.p[ax] : null; v.pid_i = fresh ? pid.i[ax] : null; v.pid_d = fresh ? pid.d[ax] : null;
  v.pid_ff = fresh ? pid.feed_forward[ax] : null; v.pid_out = fresh ? pid.output[ax] : null;
  plotRing.push(t, v);
}

// One plot: lines = [[column, colour, dash, label]]; fixed = [lo, hi] or null; wrap360 breaks
// lines that jump across north.
function drawPlot(cv, lines, fixed, wrap360, unit) {
  fit(cv);
  const g = cv.getContext('2d'), W = cv.width, H = cv.height;
  g.clearRect(0, 0, W, H);
  const span = Number($('plot_window').value);
  const r = plotRing;
  if (r.len < 2) { g.fillStyle = '#667'; g.fillText('no data yet', 44, 20); return; }
  const t1 = r.last(), t0 = t1 - span;
  let k0 = 0;
  while (k0 < r.len - 1 && r.t[r.index(k0)] < t0) k0++;
  let lo = Infinity, hi = -Infinity;
  for (const [c] of lines) {
    const col = r.cols[c];
    for (let k = k0; k < r.len; k++) { const x = col[r.index(k)]; if (x === x) { if (x < lo) lo = x; if (x > hi) hi = x; } }
  }
  if (fixed) { lo = fixed[0]; hi = fixed[1]; }
  if (!(hi >= lo)) { lo = -1; hi = 1; }
  if (hi - lo < 0.5) { const m = (hi + lo) / 2; hi = m + 0.25; lo = m - 0.25; }
  const X = (t) => ((t - t0) / span) * (W - 44) + 44, Y = (x) => H - 14 - ((x - lo) / (hi - lo)) * (H - 24);
  g.strokeStyle = '#1e2630'; g.beginPath(); g.moveTo(44, Y(0)); g.lineTo(W, Y(0)); g.stroke();
  g.fillStyle = '#778';
  g.fillText(fmt(hi, 1), 2, 12); g.fillText(fmt(lo, 1), 2, H - 14); g.fillText(unit, 2, H / 2);
  g.fillText(`-${span / 60} min`, 44, H - 2); g.fillText('now', W - 24, H - 2);
  let lx = 50;
  for (const [c, colour, dash, label] of lines) {
    const col = r.cols[c];
    g.strokeStyle = colour; g.setLineDash(dash); g.beginPath();
    let pen = false, prev = 0;
    const stride = Math.max(1, Math.floor((r.len - k0) / W));  // at most one point per pixel
    for (let k = k0; k < r.len; k += stride) {
      const i = r.index(k), x = col[i];
      if (x !== x) { pen = false; continue; }
      if (pen && wrap360 && Math.abs(x - prev) > 180) pen = false;
      if (pen) g.lineTo(X(r.t[i]), Y(x)); else g.moveTo(X(r.t[i]), Y(x));
      pen = true; prev = x;
    }
    g.stroke(); g.setLineDash([]);
    g.fillStyle = colour; g.fillText(label, lx, 12); lx += g.measureText(label).width + 14;
  }
}

// At most 4 redraws a second: a plot of minutes changes little in 50 ms.
function drawPlots() {
  const now = performance.now();
  if (now - plotLastDraw < 250) return;
  plotLastDraw = now;
  drawPlot($('plot_speed'), [['speed_sp', '#c9a227', [5, 4], 'setpoint'], ['speed', '#4aa3ff', [], 'speed']], null, false, 'm/s');
  drawPlot($('plot_heading'), [['heading_sp', '#c9a227', [5, 4], 'setpoint'], ['heading', '#4aa3ff', [], 'heading']], [0, 360], true, 'deg');
  drawPlot($('plot_xte'), [['xte', '#e07b39', [], 'cross-track error (+ right of the path)']], null, false, 'm');
  const u = $('pid_sel').value.endsWith(':2') ? 'N m' : 'N';
  drawPlot($('plot_pid'), [['pid_p', '#4aa3ff', [], 'P'], ['pid_i', '#3cb371', [], 'I'], ['pid_d', '#b57edc', [], 'D'],
    ['pid_ff', '#888', [3, 3], 'feed-forward'], ['pid_out', '#e6edf3', [], 'output']], null, false, u);
}
