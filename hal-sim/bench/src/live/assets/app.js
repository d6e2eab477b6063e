'use strict';
// The live bench page. Everything it shows comes from the bench's event
// stream (/api/events): screen patches, plot samples, console lines and the
// state; what the user does goes to the JSON API (/api/press, /api/release,
// /api/serial, /api/control). No library, no network beyond this server.

const $ = (id) => document.getElementById(id);
const JOINT_COLORS = ['#1f6fd1', '#e07b00', '#2a9d55'];
const PLOT_SECONDS = 10;
// A mouse click is a tap of at least this long: the firmware confirms a
// press over 3 frames (60 ms), as on a real panel.
const MIN_TAP_MS = 200;
const MAX_CONSOLE_LINES = 600;

const screenEl = $('screen');
const sctx = screenEl.getContext('2d');
let geometry = null;
let reachTop = null, reachSide = null;
let samples = [];
let lastState = null;
let freshStream = false;

// ---- the JSON API -----------------------------------------------------------

async function post(path, body) {
  const r = await fetch(path, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  const v = await r.json().catch(() => ({ error: `HTTP ${r.status}` }));
  if (!r.ok) throw new Error(v.error || `HTTP ${r.status}`);
  return v;
}

// ---- the screen -------------------------------------------------------------

// RGB565 (little-endian) to RGBA, with the bit replication the host's PNGs use.
function drawPatch(p) {
  // The screen's size comes with the first (full) picture: 320×240, or
  // 480×320 for the larger controllers (`--lcd`). Resizing clears it.
  if (p.x === 0 && p.y === 0 && (p.w !== screenEl.width || p.h !== screenEl.height) &&
      (p.w > screenEl.width || p.h > screenEl.height || p.w * p.h === 320 * 240)) {
    screenEl.width = p.w; screenEl.height = p.h;
  }
  const bin = atob(p.rgb565);
  const img = sctx.createImageData(p.w, p.h);
  const d = img.data;
  for (let i = 0, o = 0; i + 1 < bin.length; i += 2, o += 4) {
    const v = bin.charCodeAt(i) | (bin.charCodeAt(i + 1) << 8);
    const r = v >> 11, g = (v >> 5) & 63, b = v & 31;
    d[o] = (r << 3) | (r >> 2);
    d[o + 1] = (g << 2) | (g >> 4);
    d[o + 2] = (b << 3) | (b >> 2);
    d[o + 3] = 255;
  }
  sctx.putImageData(img, p.x, p.y);
  screenEl.dataset.seq = p.seq;
}

// The screen canvas's drawing area on the page (inside its border).
function screenBox() {
  const r = screenEl.getBoundingClientRect();
  const cs = getComputedStyle(screenEl);
  const bl = parseFloat(cs.borderLeftWidth) || 0, bt = parseFloat(cs.borderTopWidth) || 0;
  const br = parseFloat(cs.borderRightWidth) || 0, bb = parseFloat(cs.borderBottomWidth) || 0;
  return { left: r.left + bl, top: r.top + bt, width: r.width - bl - br, height: r.height - bt - bb };
}

function pixelOf(ev) {
  const b = screenBox();
  const clamp = (v, hi) => Math.min(hi, Math.max(0, v));
  return {
    x_px: clamp(Math.floor((ev.clientX - b.left) * screenEl.width / b.width), screenEl.width - 1),
    y_px: clamp(Math.floor((ev.clientY - b.top) * screenEl.height / b.height), screenEl.height - 1),
  };
}

// The finger: presses go out one at a time; while one is in flight only
// the latest position waits (a drag sends no backlog), and the release
// follows the last press.
const finger = { down: false, since: 0, next: null, release: false, busy: false };

function pump() {
  if (finger.busy) return;
  let req = null;
  if (finger.next) {
    req = post('/api/press', finger.next);
    finger.next = null;
  } else if (finger.release) {
    req = post('/api/release', {});
    finger.release = false;
  }
  if (!req) return;
  finger.busy = true;
  req.catch((e) => showResult(e.message, true)).finally(() => { finger.busy = false; pump(); });
}

screenEl.addEventListener('pointerdown', (ev) => {
  ev.preventDefault();
  screenEl.setPointerCapture(ev.pointerId);
  finger.down = true;
  finger.since = performance.now();
  finger.release = false;
  finger.next = pixelOf(ev);
  pump();
});
screenEl.addEventListener('pointermove', (ev) => {
  if (!finger.down) return;
  finger.next = pixelOf(ev);
  pump();
});
function lift() {
  if (!finger.down) return;
  finger.down = false;
  const wait = Math.max(0, MIN_TAP_MS - (performance.now() - finger.since));
  setTimeout(() => { if (!finger.down) { finger.release = true; pump(); } }, wait);
}
screenEl.addEventListener('pointerup', lift);
screenEl.addEventListener('pointercancel', lift);
window.addEventListener('blur', lift);

function showFinger(px) {
  const f = $('finger');
  if (!px) { f.hidden = true; return; }
  const b = screenEl.getBoundingClientRect(), w = screenEl.parentElement.getBoundingClientRect();
  const box = screenBox();
  f.style.left = `${box.left - w.left + (px[0] + 0.5) * box.width / screenEl.width}px`;
  f.style.top = `${box.top - w.top + (px[1] + 0.5) * box.height / screenEl.height}px`;
  f.hidden = b.width === 0;
}

// ---- the arm views ------------------------------------------------------------

// The top view shows the whole circle: an elbow behind the base axis
// projects to the far side of the base.
const VIEW = {
  top: { canvas: $('view-top'), ox: 170, oy: 120, scale: 52, full: true },
  side: { canvas: $('view-side'), ox: 170, oy: 160, scale: 70 },
};

// Where a workspace point (x_p, y_p) puts the arm's target: the base turns
// to α = atan2(y_p, x_p), the planar IK reaches (|x_p|, y_p) (k = 1).
function targetOf(xp, yp) {
  const a = Math.atan2(yp, xp), r = Math.abs(xp);
  return { top: [r * Math.cos(a), r * Math.sin(a)], side: [r, yp] };
}

function buildReach() {
  const m = geometry.map;
  const make = (v, key) => {
    const c = document.createElement('canvas');
    c.width = v.canvas.width; c.height = v.canvas.height;
    const g = c.getContext('2d');
    g.fillStyle = '#cdebd7';
    const s = Math.max(1.5, v.scale / m.scale * 1.6);
    geometry.reach_rows.forEach((row, j) => {
      for (let i = 0; i < row.length; i++) {
        if (row[i] !== '1') continue;
        const xp = (2 * i + 1 - 2 * m.origin_x) / (2 * m.scale), yp = (2 * (m.h - j) - 1) / (2 * m.scale);
        const p = targetOf(xp, yp)[key];
        g.fillRect(v.ox + p[0] * v.scale - s / 2, v.oy - p[1] * v.scale - s / 2, s, s);
      }
    });
    return c;
  };
  reachTop = make(VIEW.top, 'top');
  reachSide = make(VIEW.side, 'side');
}

function dot(g, v, p, r, fill, stroke) {
  g.beginPath();
  g.arc(v.ox + p[0] * v.scale, v.oy - p[1] * v.scale, r, 0, 2 * Math.PI);
  if (fill) { g.fillStyle = fill; g.fill(); }
  if (stroke) { g.strokeStyle = stroke; g.lineWidth = 2; g.stroke(); }
}

function frame(g, v, reach, label) {
  const c = v.canvas;
  g.clearRect(0, 0, c.width, c.height);
  if (reach) g.drawImage(reach, 0, 0);
  const rmax = geometry ? geometry.l2 + geometry.l3 : 2;
  g.strokeStyle = '#b7c0cc'; g.setLineDash([4, 4]); g.lineWidth = 1;
  g.beginPath(); g.arc(v.ox, v.oy, rmax * v.scale, v.full ? 0 : Math.PI, 2 * Math.PI); g.stroke();
  g.setLineDash([]);
  g.strokeStyle = '#8b96a5';
  g.beginPath(); g.moveTo(8, v.oy); g.lineTo(c.width - 8, v.oy); g.stroke();
  if (v.full) { g.beginPath(); g.moveTo(v.ox, 8); g.lineTo(v.ox, c.height - 8); g.stroke(); }
  g.fillStyle = '#66707f'; g.font = '11px system-ui, sans-serif';
  g.fillText(label, 8, 14);
}

function polyline(g, v, pts, color, width) {
  g.strokeStyle = color; g.lineWidth = width; g.lineCap = 'round'; g.lineJoin = 'round';
  g.beginPath();
  pts.forEach((p, i) => (i ? g.lineTo : g.moveTo).call(g, v.ox + p[0] * v.scale, v.oy - p[1] * v.scale));
  g.stroke();
}

// The gripper's two jaws at the tip, along the forearm: spread 40° each
// way when open (0°), together when closed (90°).
function drawJaws(g, v, elbow, tip, gripDeg) {
  const dir = Math.atan2(tip[1] - elbow[1], tip[0] - elbow[0]);
  const spread = (1 - Math.min(Math.max(gripDeg, 0), 90) / 90) * 40 * Math.PI / 180;
  const len = 0.16;
  for (const side of [-1, 1]) {
    const a = dir + side * spread;
    polyline(g, v, [tip, [tip[0] + len * Math.cos(a), tip[1] + len * Math.sin(a)]], '#5b6573', 3);
  }
}

function drawViews(st) {
  const arm = st.arm, tgt = st.target;
  const t = VIEW.top, s = VIEW.side;
  const gt = t.canvas.getContext('2d'), gs = s.canvas.getContext('2d');
  frame(gt, t, reachTop, 'x → (0° base) · y ↑ (90°)');
  frame(gs, s, reachSide, 'reach → · height ↑ (shoulder at the origin)');
  // The base pedestal in the side view.
  gs.fillStyle = '#c5ccd6'; gs.fillRect(s.ox - 14, s.oy, 28, 40);
  if (tgt) {
    // A refused touch is drawn grey: the arm does not go there.
    const p = targetOf(tgt.x_p, tgt.y_p), ring = tgt.refused ? '#8b96a5' : '#c62828';
    dot(gt, t, p.top, 7, null, ring);
    dot(gs, s, p.side, 7, null, ring);
  }
  if (arm) {
    const a = arm.angles_deg[0] * Math.PI / 180;
    const onPlane = (q) => [q[0] * Math.cos(a), q[0] * Math.sin(a)];
    polyline(gt, t, [[0, 0], onPlane(arm.elbow), onPlane(arm.tip)], '#1d2430', 6);
    // Joints coloured as in the plots: base, shoulder, elbow.
    dot(gt, t, [0, 0], 6, JOINT_COLORS[0]);
    dot(gt, t, onPlane(arm.elbow), 4.5, JOINT_COLORS[2]);
    dot(gt, t, onPlane(arm.tip), 4.5, '#1d2430');
    polyline(gs, s, [[0, 0], arm.elbow, arm.tip], '#1d2430', 6);
    dot(gs, s, [0, 0], 6, JOINT_COLORS[1]);
    dot(gs, s, arm.elbow, 4.5, JOINT_COLORS[2]);
    dot(gs, s, arm.tip, 4.5, '#1d2430');
    if (st.grip_deg != null) drawJaws(gs, s, arm.elbow, arm.tip, st.grip_deg);
    gt.fillStyle = '#1d2430'; gt.font = '12px system-ui, sans-serif';
    gt.fillText(`α = ${arm.angles_deg[0].toFixed(1)}°`, t.canvas.width - 86, 14);
    $('arm-views').dataset.angles = arm.angles_deg.map((x) => x.toFixed(3)).join(',');
  }
}

// ---- the plots ----------------------------------------------------------------

function plot(canvas, series, tNow, unit, symmetric) {
  const g = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height, L = 46, R = 8, T = 8, B = 20;
  g.clearRect(0, 0, W, H);
  let lo = Infinity, hi = -Infinity;
  for (const p of series) for (let j = 1; j < 4; j++) { lo = Math.min(lo, p[j]); hi = Math.max(hi, p[j]); }
  if (!isFinite(lo)) { lo = -1; hi = 1; }
  if (symmetric) { const m = Math.max(Math.abs(lo), Math.abs(hi), 5); lo = -m; hi = m; }
  if (hi - lo < 10) { const c = (hi + lo) / 2; lo = c - 5; hi = c + 5; }
  const pad = (hi - lo) * 0.08; lo -= pad; hi += pad;
  const x = (t) => L + (t - (tNow - PLOT_SECONDS)) / PLOT_SECONDS * (W - L - R);
  const y = (v) => T + (hi - v) / (hi - lo) * (H - T - B);
  g.font = '11px system-ui, sans-serif'; g.fillStyle = '#66707f'; g.strokeStyle = '#e3e8ee'; g.lineWidth = 1;
  const step = niceStep((hi - lo) / 4);
  for (let v = Math.ceil(lo / step) * step; v <= hi; v += step) {
    g.beginPath(); g.moveTo(L, y(v)); g.lineTo(W - R, y(v)); g.stroke();
    g.fillText(`${+v.toFixed(1)}`, 4, y(v) + 4);
  }
  for (let s = 0; s <= PLOT_SECONDS; s += 2) g.fillText(`${s - PLOT_SECONDS} s`, x(tNow - PLOT_SECONDS + s) - 10, H - 5);
  g.fillText(unit, L + 4, T + 10);
  for (let j = 1; j < 4; j++) {
    g.strokeStyle = JOINT_COLORS[j - 1]; g.lineWidth = 1.6;
    g.beginPath();
    let started = false, prevT = -Infinity;
    for (const p of series) {
      if (p[0] < tNow - PLOT_SECONDS) continue;
      // A gap (power cycle, reset) breaks the line.
      if (started && p[0] - prevT < 0.1) g.lineTo(x(p[0]), y(p[j])); else g.moveTo(x(p[0]), y(p[j]));
      started = true; prevT = p[0];
    }
    g.stroke();
  }
}

function niceStep(raw) {
  const e = Math.pow(10, Math.floor(Math.log10(raw)));
  for (const m of [1, 2, 5, 10]) if (m * e >= raw) return m * e;
  return 10 * e;
}

// Joint velocities as the least-squares slope over 9 frames (0.16 s): the
// firmware sends whole microseconds (0.1°), so a plain difference of two
// 20 ms frames jumps in steps of 5 °/s, and a shorter window still shows
// that rounding as a ripple.
const SLOPE_HALF = 4;
function velocities(s) {
  const out = [];
  for (let i = SLOPE_HALF; i + SLOPE_HALF < s.length; i++) {
    const w = s.slice(i - SLOPE_HALF, i + SLOPE_HALF + 1);
    // Frames of one run only (a power cycle or reset leaves a gap).
    if (w[w.length - 1][0] - w[0][0] > 0.03 * 2 * SLOPE_HALF) continue;
    const tm = w.reduce((a, p) => a + p[0], 0) / w.length;
    const den = w.reduce((a, p) => a + (p[0] - tm) ** 2, 0);
    const v = [s[i][0]];
    for (let j = 1; j < 4; j++) {
      const am = w.reduce((a, p) => a + p[j], 0) / w.length;
      v.push(w.reduce((a, p) => a + (p[0] - tm) * (p[j] - am), 0) / den);
    }
    out.push(v);
  }
  return out;
}

function drawPlots(tNow) {
  samples = samples.filter((p) => p[0] >= tNow - PLOT_SECONDS - 1);
  plot($('plot-angle'), samples, tNow, 'angle °', false);
  plot($('plot-velocity'), velocities(samples), tNow, 'velocity °/s', true);
}

// ---- header, table, console ---------------------------------------------------

function setPill(el, text, cls) {
  el.textContent = text;
  el.className = `pill ${cls || ''}`;
}

const STATE_CLASS = { holding: 'ok', moving: 'warn', paused: 'warn', checking: 'warn', stopped: 'bad', stalled: 'bad', halted: 'bad' };

function showState(st) {
  lastState = st;
  setPill($('state'), st.state, STATE_CLASS[st.state]);
  $('clock').textContent = `t = ${st.t_s.toFixed(2)} s`;
  const b = st.bench || {};
  if (b.halted) setPill($('pacing'), 'firmware halted: power-cycle', 'bad');
  else if (b.behind) {
    setPill($('pacing'), `simulator BEHIND real time: ×${(b.ratio_5s || 0).toFixed(3)} over 5 s, lag ${Math.round(b.lag_ms)} ms` +
      (b.slipped_s > 0 ? `, ${b.slipped_s.toFixed(2)} s dropped so far` : ''), 'bad');
  }
  else if (b.ratio_60s != null) setPill($('pacing'), `real time ×${b.ratio_60s.toFixed(4)} over ${Math.round(b.window_60s_s)} s`, 'ok');
  $('chk-noise').checked = !!b.noise;
  for (let j = 0; j < 3; j++) {
    const p = st.pulses_us[j], a = st.angles_deg[j];
    $(`pulse-${j}`).textContent = p == null ? '–' : p.toFixed(2);
    $(`angle-${j}`).textContent = a == null ? '–' : a.toFixed(2);
    $(`target-${j}`).textContent = st.target ? st.target.angles_deg[j].toFixed(2) : '–';
  }
  $('pulse-3').textContent = st.grip_pulse_us == null ? '–' : st.grip_pulse_us.toFixed(2);
  $('angle-3').textContent = st.grip_deg == null ? '–' : st.grip_deg.toFixed(2);
  const t = st.target;
  $('target-info').textContent = t
    ? `Last touch the firmware confirmed: map pixel (${t.px[0]}, ${t.px[1]}) → point (${t.x_p.toFixed(3)}, ${t.y_p.toFixed(3)}), zone ${t.condition}, α ${t.alpha_deg.toFixed(2)}°` +
      (t.refused ? ` — refused: ${t.refused}` : '')
    : 'No map target (a goto or move over the serial port clears it): touch the map, top left of the screen.';
  showFinger(st.finger);
  samples.push(...st.samples);
  drawViews(st);
  drawPlots(st.t_s);
}

function lineClass(l) {
  if (l.d === 'tx') return 'tx';
  if (l.d === 'bench') return 'bench';
  const s = l.s;
  if (s.startsWith('t ')) return 'tel';
  if (s.startsWith('ok')) return 'ok';
  if (s.startsWith('err')) return 'err';
  if (s.startsWith('warn')) return 'warn';
  return 'info';
}

function addConsole(lines) {
  const log = $('console-log');
  const atBottom = log.scrollHeight - log.scrollTop - log.clientHeight < 30;
  for (const l of lines) {
    const div = document.createElement('div');
    div.className = lineClass(l);
    div.textContent = (l.d === 'tx' ? '> ' : l.d === 'bench' ? '# ' : '') + l.s;
    log.appendChild(div);
  }
  while (log.childElementCount > MAX_CONSOLE_LINES) log.firstElementChild.remove();
  if (atBottom) log.scrollTop = log.scrollHeight;
}

function showResult(text, bad) {
  const r = $('control-result');
  r.textContent = text;
  r.className = `result ${bad ? 'bad' : ''}`;
}

// ---- the assistive switch --------------------------------------------------------

// The switch button: held by the pointer (down until up or until it leaves
// the button) or by Space/Enter. Levels go out one at a time and only the
// latest waits, so a quick press and release arrive in order; the release
// follows the press by MIN_TAP_MS at least, so a click is a press the
// firmware counts (its hold is 0.10 s), as a click on the screen is.
const sw = { want: false, sent: false, since: 0, busy: false, keys: new Set() };

function pumpSwitch() {
  if (sw.busy || sw.want === sw.sent) return;
  const down = sw.want;
  sw.busy = true;
  post('/api/switch', { down })
    .then(() => { sw.sent = down; })
    .catch((e) => { showResult(`switch: ${e.message}`, true); sw.sent = down; })
    .finally(() => { sw.busy = false; pumpSwitch(); });
}

function setSwitch(down) {
  const btn = $('btn-switch');
  if (down) {
    if (!sw.want) sw.since = performance.now();
    sw.want = true;
    btn.classList.add('held');
    btn.setAttribute('aria-pressed', 'true');
    pumpSwitch();
    return;
  }
  if (!sw.want) return;
  const wait = Math.max(0, MIN_TAP_MS - (performance.now() - sw.since));
  setTimeout(() => {
    // Still released (not pressed again meanwhile).
    if (sw.keys.size || btn.dataset.pointer === 'down') return;
    sw.want = false;
    btn.classList.remove('held');
    btn.setAttribute('aria-pressed', 'false');
    pumpSwitch();
  }, wait);
}

{
  const btn = $('btn-switch');
  btn.addEventListener('pointerdown', (ev) => {
    if (ev.button !== 0) return;
    ev.preventDefault();
    btn.dataset.pointer = 'down';
    setSwitch(true);
  });
  const up = () => {
    if (btn.dataset.pointer !== 'down') return;
    btn.dataset.pointer = '';
    setSwitch(false);
  };
  btn.addEventListener('pointerup', up);
  btn.addEventListener('pointerleave', up);
  btn.addEventListener('pointercancel', up);
  btn.addEventListener('keydown', (ev) => {
    if (ev.key !== ' ' && ev.key !== 'Enter') return;
    ev.preventDefault();
    if (ev.repeat) return;
    sw.keys.add(ev.key);
    setSwitch(true);
  });
  btn.addEventListener('keyup', (ev) => {
    if (ev.key !== ' ' && ev.key !== 'Enter') return;
    ev.preventDefault();
    sw.keys.delete(ev.key);
    if (!sw.keys.size) setSwitch(false);
  });
  btn.addEventListener('blur', () => { sw.keys.clear(); up(); setSwitch(false); });
  // A long touch on a touch screen would open the context menu.
  btn.addEventListener('contextmenu', (ev) => ev.preventDefault());
  // The window losing focus mid-press loses the pointer's and keys' ups.
  window.addEventListener('blur', () => { sw.keys.clear(); up(); setSwitch(false); });
}

// ---- controls and console input ------------------------------------------------

async function control(body, describe) {
  try {
    showResult(describe(await post('/api/control', body)));
  } catch (e) {
    showResult(e.message, true);
  }
}

$('btn-reset').onclick = () => control({ action: 'reset' }, (v) => `external reset #${v.external_resets} at t = ${v.t_s.toFixed(2)} s: RAM kept, the pulses resume`);
$('btn-power').onclick = () => control({ action: 'power_cycle' }, (v) => `power cycle: power-up #${v.power_ups} at t = ${v.t_s.toFixed(2)} s`);
$('btn-eeprom').onclick = () => {
  const addr = Number($('eeprom-addr').value);
  const hex = (b) => `0x${b.toString(16).padStart(2, '0')}`;
  control({ action: 'corrupt_eeprom', addr }, (v) => `EEPROM byte ${v.addr}: ${hex(v.old)} → ${hex(v.new)}; the firmware reads it at the next power-up`);
};
$('chk-noise').onchange = (ev) => control({ action: ev.target.checked ? 'noise_on' : 'noise_off' }, (v) => (v.noise ? 'noisy panel' : 'clean panel'));
$('btn-stall').onclick = () => control({ action: 'stall' }, (v) => `frame loop stalled at t = ${v.stalled_at_s.toFixed(2)} s: the watchdog should reset the chip`);

const typed = [];
let historyAt = 0;
$('console-form').onsubmit = async (ev) => {
  ev.preventDefault();
  const input = $('console-input');
  const line = input.value;
  if (!line.trim()) return;
  typed.push(line);
  historyAt = typed.length;
  input.value = '';
  try {
    await post('/api/serial', { line });
  } catch (e) {
    addConsole([{ d: 'bench', s: `not sent: ${e.message}` }]);
  }
};
$('console-input').addEventListener('keydown', (ev) => {
  if (ev.key !== 'ArrowUp' && ev.key !== 'ArrowDown') return;
  historyAt = Math.max(0, Math.min(typed.length, historyAt + (ev.key === 'ArrowUp' ? -1 : 1)));
  ev.target.value = typed[historyAt] || '';
  ev.preventDefault();
});

// ---- the event stream ------------------------------------------------------------

function connect() {
  const es = new EventSource('/api/events');
  es.onopen = () => { setPill($('link'), 'live', 'ok'); freshStream = true; };
  es.onerror = () => setPill($('link'), 'disconnected, retrying…', 'bad');
  es.addEventListener('screen', (e) => drawPatch(JSON.parse(e.data)));
  es.addEventListener('history', (e) => { samples = JSON.parse(e.data).samples; });
  es.addEventListener('serial', (e) => {
    // A (re)connected stream starts with the console's backlog.
    if (freshStream) { $('console-log').textContent = ''; freshStream = false; }
    addConsole(JSON.parse(e.data).lines);
  });
  es.addEventListener('state', (e) => showState(JSON.parse(e.data)));
}

// For scripts and tests: where a screen pixel's centre is on the page.
window.bench = {
  pixelToClient(x, y) {
    const b = screenBox();
    return { x: b.left + (x + 0.5) * b.width / screenEl.width, y: b.top + (y + 0.5) * b.height / screenEl.height };
  },
  state: () => lastState,
};

fetch('/api/geometry').then((r) => r.json()).then((g) => {
  geometry = g;
  $('screen-caption').textContent = `${g.lcd.toUpperCase()} ${g.screen[0]}×${g.screen[1]}, touch wiring ${g.wiring}, rebuilt from the firmware's writes on the LCD bus`;
  buildReach();
  if (lastState) drawViews(lastState);
}).catch((e) => showResult(`geometry: ${e.message}`, true));
window.addEventListener('resize', () => lastState && showFinger(lastState.finger));
connect();
