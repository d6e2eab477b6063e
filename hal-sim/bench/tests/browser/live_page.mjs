// Drives the live bench page in Debian's headless Chromium through
// Playwright, as a person would: click on the map in the screen image and
// watch the drawn arm reach the target, click STOP on the screen image and
// see the pulses freeze, type `status` in the console and see the reply,
// then `resume` and `grip 60` and see the gripper's row reach 60°, then
// play a scripted tremor through `/api/finger` and see where it committed,
// then `switch on` and hold the Switch button with the mouse, with Space and
// with a pointer that leaves it: the bench closes and opens PA0 each time,
// and the firmware's scan fixes a column and a row.
// Run by hal-sim/bench/tests/live_page.rs, which starts the bench and passes:
//   node live_page.mjs URL OUT_DIR MAP_X,MAP_Y TARGET_B,TARGET_S,TARGET_E STOP_X,STOP_Y
// Prints one line per step; exits 0 when every check held, 1 otherwise.
// Bounded: every wait has a timeout and the whole run stops after 90 s.
import { chromium } from 'playwright-core';
import { mkdtempSync, rmSync, mkdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const [url, outDir, mapArg, targetArg, stopArg] = process.argv.slice(2);
const nums = (s) => s.split(',').map(Number);
const [mapX, mapY] = nums(mapArg);
const target = nums(targetArg);
const [stopX, stopY] = nums(stopArg);
const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';

const profile = mkdtempSync(join(tmpdir(), 'touch-arm-live-chromium-'));
mkdirSync(outDir, { recursive: true });
let context = null;
const overall = setTimeout(() => fail(new Error('the page test took over 90 s')), 90_000);

async function fail(e) {
  console.log(`FAIL: ${e.message}`);
  try {
    const page = context && context.pages()[0];
    if (page) await page.screenshot({ path: join(outDir, 'live-page-failure.png'), fullPage: true });
  } catch { /* the failure itself matters more */ }
  await cleanup();
  process.exit(1);
}

async function cleanup() {
  clearTimeout(overall);
  if (context) await context.close().catch(() => {});
  rmSync(profile, { recursive: true, force: true });
}

async function state(page) {
  return page.evaluate(async () => (await fetch('/api/state')).json());
}

// The console's lines as the page shows them.
async function consoleLines(page) {
  return page.evaluate(() => [...document.querySelectorAll('#console-log div')].map((d) => d.textContent));
}

// Waits (5 s at most) until the bench's switch is `down` (`/api/bench`).
async function switchIs(page, down, what) {
  const end = Date.now() + 5_000;
  for (;;) {
    const b = await page.evaluate(async () => (await fetch('/api/bench')).json());
    if (b.switch === down) return;
    if (Date.now() > end) throw new Error(`${what}: /api/bench switch is ${b.switch}`);
    await page.waitForTimeout(50);
  }
}

async function main() {
  context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    viewport: { width: 1440, height: 1000 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
      '--disable-component-update', '--disable-sync'],
  });
  const page = context.pages()[0] || await context.newPage();
  page.setDefaultTimeout(20_000);
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForFunction(() => document.getElementById('link').textContent === 'live');
  await page.waitForFunction(() => document.getElementById('state').textContent === 'holding');
  await page.waitForFunction(() => Number(document.getElementById('screen').dataset.seq) > 0);
  console.log('page live, firmware holding the home pose');

  // 1. Click on the map: the drawn arm's angles reach the target.
  const at = await page.evaluate(([x, y]) => window.bench.pixelToClient(x, y), [mapX, mapY]);
  await page.mouse.click(at.x, at.y);
  await page.waitForFunction((want) => {
    const a = document.getElementById('arm-views').dataset.angles;
    if (!a) return false;
    return a.split(',').map(Number).every((v, j) => Math.abs(v - want[j]) < 0.2);
  }, target);
  const drawn = await page.evaluate(() => document.getElementById('arm-views').dataset.angles);
  console.log(`map click at pixel (${mapX}, ${mapY}): drawn angles ${drawn}, target ${target.join(',')}`);
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(outDir, 'live-page.png'), fullPage: true });

  // 2. A long move, then STOP on the screen image: the pulses freeze.
  const back = await page.evaluate(() => fetch('/api/serial', { method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ line: 'goto 20 150 -30' }) }).then((r) => r.json()));
  if (!back.replies.length || !back.replies[back.replies.length - 1].startsWith('ok goto')) throw new Error(`goto: ${JSON.stringify(back)}`);
  await page.waitForFunction(() => document.getElementById('state').textContent === 'moving');
  await page.waitForTimeout(1000);
  const stop = await page.evaluate(([x, y]) => window.bench.pixelToClient(x, y), [stopX, stopY]);
  await page.mouse.click(stop.x, stop.y);
  await page.waitForFunction(() => document.getElementById('state').textContent === 'stopped');
  await page.waitForTimeout(200);
  const s1 = await state(page);
  const d1 = await page.evaluate(() => document.getElementById('arm-views').dataset.angles);
  await page.waitForTimeout(1000);
  const s2 = await state(page);
  const d2 = await page.evaluate(() => document.getElementById('arm-views').dataset.angles);
  for (let j = 0; j < 3; j++) {
    if (Math.abs(s1.pulses_us[j] - s2.pulses_us[j]) > 0.25) throw new Error(`pulses moved after STOP: ${s1.pulses_us} -> ${s2.pulses_us}`);
  }
  // Within the pin measurement's jitter (0.25 µs = 0.025°).
  if (nums(d1).some((a, j) => Math.abs(a - nums(d2)[j]) > 0.03)) throw new Error(`the drawn arm moved after STOP: ${d1} -> ${d2}`);
  if (s1.pulses_us.every((p, j) => Math.abs(p - [1500, 1500, 1500][j]) < 1)) throw new Error('STOP came before the move started');
  console.log(`STOP on the screen: pulses frozen at ${s2.pulses_us.map((p) => p.toFixed(2)).join(', ')} us`);
  await page.screenshot({ path: join(outDir, 'live-page-stopped.png'), fullPage: true });

  // 3. The console: type `status`, the reply shows.
  await page.fill('#console-input', 'status');
  await page.press('#console-input', 'Enter');
  await page.waitForFunction(() => [...document.querySelectorAll('#console-log div')]
    .some((d) => d.textContent.startsWith('ok status stopped')));
  const reply = await page.evaluate(() => [...document.querySelectorAll('#console-log div')]
    .map((d) => d.textContent).filter((t) => t.startsWith('ok status')).pop());
  console.log(`console: ${reply}`);
  // 4. The gripper: `resume`, then `grip 60`; its row in the joints table
  // shows 60° (the default calibration: 600 µs + 10 µs per degree).
  for (const line of ['resume', 'grip 60']) {
    await page.fill('#console-input', line);
    await page.press('#console-input', 'Enter');
    await page.waitForFunction((l) => [...document.querySelectorAll('#console-log div')]
      .some((d) => d.textContent.startsWith(`ok ${l.split(' ')[0]}`)), line);
  }
  await page.waitForFunction(() => Math.abs(Number(document.getElementById('angle-3').textContent) - 60) < 0.05,
    null, { timeout: 15_000 });
  const grip = await page.evaluate(() => [3].map((j) => [document.getElementById(`pulse-${j}`).textContent,
    document.getElementById(`angle-${j}`).textContent])[0]);
  console.log(`gripper row: pulse ${grip[0]} us, angle ${grip[1]} deg`);
  // 5. A scripted finger (`POST /api/finger`): a 6 Hz tremor of 1 mm (5.6 px
  // on the 2.8" glass) for 0.6 s on another map pixel, then the lift. The
  // firmware commits on the lift-off at the contact's centre: the page's
  // "last touch" names a pixel within 2 of the one aimed at.
  const [fx, fy] = [mapX - 30, mapY + 10];
  const samples = [];
  for (let t = 0; t <= 600; t += 5) {
    const d = 5.6 * Math.sin(2 * Math.PI * 6 * t / 1000);
    samples.push([t, fx + d, fy, 1]);
  }
  samples.push([600, fx, fy, 0]);
  const started = await page.evaluate(async (body) => {
    const r = await fetch('/api/finger', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
    return r.json();
  }, { samples });
  if (typeof started.t_s !== 'number') throw new Error(`/api/finger answered ${JSON.stringify(started)}`);
  await page.waitForFunction(([x, y]) => {
    const m = /map pixel \((\d+), (\d+)\)/.exec(document.getElementById('target-info').textContent);
    return m && Math.abs(Number(m[1]) - x) <= 2 && Math.abs(Number(m[2]) - y) <= 2;
  }, [fx, fy], { timeout: 15_000 });
  const info = await page.evaluate(() => document.getElementById('target-info').textContent);
  console.log(`scripted tremor at pixel (${fx}, ${fy}), started at t = ${started.t_s.toFixed(2)} s: ${info}`);
  await page.screenshot({ path: join(outDir, 'live-page-console.png'), fullPage: true });

  // 6. The assistive switch. Scanning runs while the arm is idle (a press
  // while it moves is STOP), so first the tremor's move ends.
  await page.waitForFunction(() => document.getElementById('state').textContent === 'holding', null, { timeout: 15_000 });
  await page.fill('#console-input', 'switch on');
  await page.press('#console-input', 'Enter');
  await page.waitForFunction(() => [...document.querySelectorAll('#console-log div')]
    .some((d) => /^> switch on$/.test(d.textContent)));
  // Mouse: down on the button (the bench's PA0 low), held 0.3 s, up.
  const box = await page.locator('#btn-switch').boundingBox();
  const [bx, by] = [box.x + box.width / 2, box.y + box.height / 2];
  await page.mouse.move(bx, by);
  await page.mouse.down();
  await switchIs(page, true, 'the mouse holds the switch');
  await page.waitForTimeout(300);
  await page.mouse.up();
  await switchIs(page, false, 'the mouse let go');
  // Space on the focused button, after the firmware's repeat (0.20 s).
  await page.waitForTimeout(600);
  await page.focus('#btn-switch');
  await page.keyboard.down('Space');
  await switchIs(page, true, 'Space holds the switch');
  await page.waitForTimeout(300);
  await page.keyboard.up('Space');
  await switchIs(page, false, 'Space let go');
  // A pointer that slides off the button opens the switch.
  await page.waitForTimeout(600);
  await page.mouse.move(bx, by);
  await page.mouse.down();
  await switchIs(page, true, 'the mouse holds the switch again');
  await page.mouse.move(bx, by + 200);
  await switchIs(page, false, 'the pointer left the button');
  await page.mouse.up();
  const seen = await consoleLines(page);
  const notes = seen.filter((t) => t === '# switch closed (PA0 low)').length;
  if (notes !== 3) throw new Error(`${notes} switch closings on the console, not 3`);
  // The firmware: `switch on` answered, then a column and a row fixed.
  for (const want of ['ok switch on sweep ', 'info switch column ', 'info switch row ']) {
    await page.waitForFunction((w) => [...document.querySelectorAll('#console-log div')]
      .some((d) => d.textContent.startsWith(w)), want, { timeout: 5_000 })
      .catch(() => { throw new Error(`no ${JSON.stringify(want)} on the console`); });
  }
  const picked = (await consoleLines(page)).filter((t) => t.startsWith('info switch '));
  console.log(`switch button: mouse, Space and a sliding pointer closed PA0; firmware: ${picked.join(' · ')}`);
  await page.screenshot({ path: join(outDir, 'live-page-switch.png'), fullPage: true });
  if (errors.length) throw new Error(`errors on the page: ${errors.join('; ')}`);
  await cleanup();
  console.log('PASS');
}

main().catch(fail);
