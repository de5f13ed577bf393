// End-to-end test and timing benchmark of the web explorer in headless Chromium (Debian's
// chromium, driven by playwright-core). The page reports its state in #lopin-status (see
// lopin_explorer::page_report): this script waits for the first converged solve, checks that
// the 3D view is drawn (not blank) in a screenshot, clicks the friction slider's rail where the
// page says it is and waits for each warm re-solve to converge, then switches the section on
// and scrubs time (each must change the picture), pins the current value as A and shows it side
// by side with the current one (two viewports, both drawn), and fails on any console error;
// then, in a second page whose solver's worker script cannot load, waits for the failure the
// page must show.
//
//   node web/e2e/explorer.cjs URL OUT_DIR [MOVES]
//
// Writes OUT_DIR/web-first.png, web-after.png, web-section.png, web-time.png,
// web-side-by-side.png and OUT_DIR/web-e2e.json (timings).
//
// The random mode: seeded random use of the page once its first solve converged — clicks on
// the controls it reports (anywhere on a rail, and past its ends), clicks, drags, double-clicks
// and wheel turns anywhere below the top bar (which holds the scene picker), orbit and pan drags
// in the 3D view, text typed (numbers at the extremes, text that is no number) and keys,
// pauses — at most LOPIN_UI_CLICKS actions (default 300) and LOPIN_UI_SECONDS seconds (default
// 90). Fails on any console error, page error, failed request or HTTP error, on a page that
// stops answering, on a solve that breaks down (non-finite values) or ends unconverged, and on
// a blank 3D view (screenshots every 50 actions and at the end). LOPIN_UI_SEED (decimal or
// 0x-hexadecimal, default fixed; its low 32 bits) picks the sequence; a failure prints it with
// the last actions.
//
//   node web/e2e/explorer.cjs --random URL OUT_DIR
//
// Writes OUT_DIR/web-random.png (the end) and OUT_DIR/web-random.json (every action).
"use strict";
const path = require("path");
const fs = require("fs");
const tools = process.env.WEB_TOOLS;
if (!tools) {
  console.error("WEB_TOOLS is not set (run through scripts/test-web.sh)");
  process.exit(2);
}
const { chromium } = require(path.join(tools, "npm/node_modules/playwright-core"));

const randomMode = process.argv[2] === "--random";
const [url, outDir, movesArg] = process.argv.slice(randomMode ? 3 : 2);
const moves = Number(movesArg || 3);
// where each move clicks along the friction rail (fractions of its width)
const FRACTIONS = [0.75, 0.3, 0.55, 0.2, 0.65, 0.4, 0.85, 0.1, 0.5, 0.7];
const LOAD_TIMEOUT_MS = 180000;
const RESOLVE_TIMEOUT_MS = 120000;
const VIEWPORT = { width: 1280, height: 800 };

function fail(msg) {
  throw new Error(msg);
}

// Fails on any console error, page error or failed request the page reported.
function failOnErrors(errors) {
  if (errors.length > 0) fail(`console errors:\n  ${errors.join("\n  ")}`);
}

async function status(page) {
  return page.evaluate(() => {
    const el = document.getElementById("lopin-status");
    const d = { ...el.dataset };
    d.title = document.title;
    d.now = performance.now();
    return d;
  });
}

function rect(attr, what) {
  const r = (attr || "").split(",").map(Number);
  if (r.length !== 4 || r.some((x) => !Number.isFinite(x)) || r[2] <= 0 || r[3] <= 0) {
    fail(`the page reports no ${what} (got "${attr}")`);
  }
  return r;
}

function control(st, name) {
  const r = JSON.parse(st.controls || "{}")[name];
  if (!r || r[2] <= 0 || r[3] <= 0) fail(`the page reports no "${name}" control: ${st.controls}`);
  return r;
}

// Clicks a control where the page says it is now, until `predicate` holds (at most 5 clicks):
// the page draws on between reading a position and the click landing (a solve's report, the
// background study), so a slow frame may swallow a click or a moved layout misplace it.
// `at(box)` gives the point to click in the control's box; `prepare`, if given, runs before
// each click (to restore a state a stray click undid).
async function clickUntil(page, name, at, predicate, what, prepare) {
  for (let attempt = 0; attempt < 5; attempt++) {
    if (prepare) await prepare();
    const [x, y] = at(control(await status(page), name));
    await page.mouse.click(x, y);
    try {
      await page.waitForFunction(predicate, null, { timeout: 3000, polling: 20 });
      return status(page);
    } catch (e) {
      // stale position (or a slow frame): read it again and retry
    }
  }
  return waitFor(page, predicate, null, what);
}

async function waitFor(page, predicate, arg, what) {
  try {
    await page.waitForFunction(predicate, arg, { timeout: 30000, polling: 20 });
  } catch (e) {
    const st = await status(page);
    fail(`${what} did not happen: ${st.title} ${JSON.stringify(st)}`);
  }
  return status(page);
}

// Region r of one or two screenshots, decoded by the browser itself: colour statistics of the
// first and, given a second, the fraction of the region's pixels that differ between them.
async function imageStats(page, pngs, r) {
  return page.evaluate(
    async ({ pngs, r }) => {
      const pixels = async (b64) => {
        const img = new Image();
        img.src = "data:image/png;base64," + b64;
        await img.decode();
        const c = document.createElement("canvas");
        c.width = img.width;
        c.height = img.height;
        const g = c.getContext("2d");
        g.drawImage(img, 0, 0);
        const [x, y, w, h] = r.map(Math.round);
        return g.getImageData(x, y, w, h).data;
      };
      const [d, other] = await Promise.all(pngs.map(pixels));
      const counts = new Map();
      for (let i = 0; i < d.length; i += 4) {
        const key = ((d[i] >> 3) << 10) | ((d[i + 1] >> 3) << 5) | (d[i + 2] >> 3);
        counts.set(key, (counts.get(key) || 0) + 1);
      }
      let background = 0;
      for (const n of counts.values()) background = Math.max(background, n);
      const n = d.length / 4;
      const stats = {
        pixels: n,
        colours: counts.size,
        non_background_fraction: 1 - background / n,
      };
      if (other) {
        let changed = 0;
        for (let i = 0; i < d.length; i += 4) {
          const diff =
            Math.abs(d[i] - other[i]) +
            Math.abs(d[i + 1] - other[i + 1]) +
            Math.abs(d[i + 2] - other[i + 2]);
          if (diff > 24) changed++;
        }
        stats.changed_fraction = changed / n;
      }
      return stats;
    },
    { pngs: pngs.map((p) => p.toString("base64")), r }
  );
}

async function changedFraction(page, a, b, r) {
  return (await imageStats(page, [a, b], r)).changed_fraction;
}

async function checkDrawn(page, file, viewRect) {
  const png = await page.screenshot({ path: file });
  const s = await imageStats(page, [png], viewRect);
  // a drawn view has the coloured mesh (viridis), the legend and the axes: many colours and a
  // good share of the view off the background
  if (s.colours < 24 || s.non_background_fraction < 0.03) {
    fail(`the 3D view looks blank in ${file}: ${JSON.stringify(s)}`);
  }
  s.png = png;
  return s;
}

async function waitConverged(page, generation, timeout) {
  await page.waitForFunction(
    (g) => {
      const d = document.getElementById("lopin-status").dataset;
      return (
        Number(d.generation) >= g &&
        (d.state === "converged" || d.state === "not-converged" || d.state === "failed")
      );
    },
    generation,
    { timeout, polling: 20 }
  );
  const st = await status(page);
  if (st.state !== "converged") {
    fail(`solve ${generation} ended ${st.state}: ${st.title} ${st.error || ""}`);
  }
  return st;
}

// Headless Chromium on SwiftShader.
async function launch() {
  const browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    headless: true,
    args: [
      "--no-sandbox",
      "--disable-gpu",
      "--disable-quic",
      "--no-first-run",
      "--disable-background-networking",
      "--disable-component-update",
      "--disable-sync",
      "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader",
    ],
  });
  return browser;
}

// A page of the viewport's size; `errors` collects its console errors, page errors, failed
// requests and HTTP errors.
async function openPage(browser, errors) {
  const context = await browser.newContext({
    viewport: VIEWPORT,
    deviceScaleFactor: 1,
  });
  const page = await context.newPage();
  page.on("console", (m) => {
    if (m.type() === "error") errors.push(`console: ${m.text()}`);
  });
  page.on("pageerror", (e) => errors.push(`page error: ${e.message}`));
  page.on("requestfailed", (r) => errors.push(`request failed: ${r.url()}`));
  page.on("response", (r) => {
    if (r.status() >= 400) errors.push(`HTTP ${r.status()}: ${r.url()}`);
  });
  return page;
}

async function main() {
  fs.mkdirSync(outDir, { recursive: true });
  const errors = [];
  const browser = await launch();
  const report = { url, moves: [] };
  try {
    const page = await openPage(browser, errors);

    await page.goto(url, { waitUntil: "load" });
    const first = await waitConverged(page, 1, LOAD_TIMEOUT_MS);
    report.first_frame_ms = Number(first.firstFrameMs);
    report.first_fields_ms = Number(first.firstFieldsMs);
    report.first_converged_ms = first.now;
    report.first_solve = {
      iterations: Number(first.iterations),
      eta: Number(first.eta),
      latency_s: Number(first.latencyS),
      solver_s: Number(first.solveS),
      engine_s: Number(first.engineS),
      setup_s: Number(first.setupS),
    };
    if (first.drawn !== "true") fail("converged, but the page reports no fields drawn");
    // the solver runs in its Web Worker (the page's frames only draw)
    report.solver = first.solver;
    if (first.solver !== "worker") fail(`the solver runs in the ${first.solver}, not in its worker`);
    // the address names the scene on screen: a link to it
    const scene = new URL(page.url()).searchParams.get("scene");
    if (scene !== first.scene) fail(`the address names scene ${scene}, the page shows ${first.scene}`);
    report.address = page.url();
    const view = rect(first.view, "3D view");
    // let the converged fields reach the screen
    await page.waitForTimeout(300);
    report.first_view = await checkDrawn(page, path.join(outDir, "web-first.png"), view);
    delete report.first_view.png;

    let last = first;
    for (let i = 0; i < moves; i++) {
      const rail = control(last, "friction");
      const frac = FRACTIONS[i % FRACTIONS.length];
      const x = rail[0] + frac * rail[2];
      const y = rail[1] + rail[3] / 2;
      const f0 = Number(last.friction);
      const g0 = Number(last.generation);
      const t0 = await page.evaluate(() => performance.now());
      await page.mouse.click(x, y);
      // the click is a parameter change: a new generation
      await page.waitForFunction(
        (g) => Number(document.getElementById("lopin-status").dataset.generation) > g,
        g0,
        { timeout: 10000, polling: 20 }
      );
      const st = await waitConverged(page, g0 + 1, RESOLVE_TIMEOUT_MS);
      const f1 = Number(st.friction);
      if (!(Math.abs(f1 - f0) > 0.05)) {
        fail(`the slider click at ${frac} of the rail moved f from ${f0} to ${f1} only`);
      }
      if (st.warm !== "true") fail(`re-solve ${st.generation} did not start warm`);
      if (st.solver !== "worker") fail(`re-solve ${st.generation} ran in the ${st.solver}`);
      report.moves.push({
        friction_from: f0,
        friction_to: f1,
        iterations: Number(st.iterations),
        eta: Number(st.eta),
        app_latency_s: Number(st.latencyS),
        solver_s: Number(st.solveS),
        engine_s: Number(st.engineS),
        click_to_converged_in_dom_s: (st.now - t0) / 1000,
      });
      last = st;
    }
    await page.waitForTimeout(300);
    const after = await checkDrawn(page, path.join(outDir, "web-after.png"), view);

    // section on: the cut changes the picture
    last = await clickUntil(
      page,
      "section",
      (box) => [box[0] + box[2] / 2, box[1] + box[3] / 2],
      () => document.getElementById("lopin-status").dataset.section === "true",
      "switching the section on"
    );
    await page.waitForTimeout(300);
    const cut = await checkDrawn(page, path.join(outDir, "web-section.png"), view);
    report.section_changed_fraction = await changedFraction(page, after.png, cut.png, view);
    if (report.section_changed_fraction < 0.02) {
      fail(`the section left the view unchanged (${report.section_changed_fraction})`);
    }

    // time scrubber at 1/5: the fields of that step reach the screen
    const time = control(last, "time");
    const step0 = Number(last.step);
    await page.mouse.click(time[0] + 0.2 * time[2], time[1] + time[3] / 2);
    last = await waitFor(
      page,
      (s0) => {
        const d = document.getElementById("lopin-status").dataset;
        return Number(d.step) !== s0 && d.shownStep === d.step && d.shownLive === "false";
      },
      step0,
      "scrubbing time"
    );
    await page.waitForTimeout(300);
    const later = await checkDrawn(page, path.join(outDir, "web-time.png"), view);
    report.time_step = { from: step0, to: Number(last.step) };
    report.time_changed_fraction = await changedFraction(page, cut.png, later.png, view);
    if (report.time_changed_fraction < 0.02) {
      fail(`scrubbing time left the view unchanged (${report.time_changed_fraction})`);
    }

    // pin A (the current value), then side by side: A's viewport on the left, the current one
    // on the right, both drawn (A from its stored picture, made at this step at once); a click
    // that landed elsewhere (on "unpin") pins A again before the next one
    const pinA = async () => {
      if ((await status(page)).pinned !== "") return;
      await clickUntil(
        page,
        "pin A",
        (box) => [box[0] + box[2] / 2, box[1] + box[3] / 2],
        () => document.getElementById("lopin-status").dataset.pinned !== "",
        "pinning A"
      );
    };
    last = await clickUntil(
      page,
      "side by side",
      (box) => [box[0] + 8, box[1] + box[3] / 2],
      () => document.getElementById("lopin-status").dataset.besideDrawn === "true",
      "showing A side by side",
      pinA
    );
    await page.waitForTimeout(300);
    const left = rect(last.beside, "viewport of A");
    const right = rect(last.view, "viewport of the current value");
    if (!(left[0] + left[2] <= right[0] && Math.abs(left[2] - right[2]) < 1)) {
      fail(`the side-by-side viewports overlap or differ in size: ${left} ${right}`);
    }
    const sideFile = path.join(outDir, "web-side-by-side.png");
    const sideA = await checkDrawn(page, sideFile, left);
    const sideB = await checkDrawn(page, sideFile, right);
    report.side_by_side = { pinned: Number(last.pinned), a: sideA, b: sideB };
    for (const s of [after, cut, later, sideA, sideB]) delete s.png;
    report.after_view = after;
    report.title = last.title;

    // a page whose solver's worker cannot load says so (no endless "starting")
    const broken = await browser.newPage({ viewport: VIEWPORT });
    await broken.route("**/lopin_worker.js", (r) => r.abort());
    await broken.goto(url, { waitUntil: "load" });
    await broken.waitForFunction(
      () => document.getElementById("lopin-status").dataset.state === "failed",
      null,
      { timeout: LOAD_TIMEOUT_MS, polling: 50 }
    );
    const down = await status(broken);
    if (!/the solver stopped: .*lopin_worker\.js/.test(down.error)) {
      fail(`without its worker's script the page says: ${down.error}`);
    }
    report.without_worker = down.error;
    await broken.close();
  } finally {
    await browser.close();
  }
  report.console_errors = errors;
  fs.writeFileSync(path.join(outDir, "web-e2e.json"), JSON.stringify(report, null, 2));
  failOnErrors(errors);
  return report;
}

// mulberry32: a small seeded generator of numbers in [0, 1)
function generator(seed) {
  let a = Number(BigInt.asUintN(32, BigInt(seed)));
  return () => {
    a = (a + 0x6d2b79f5) | 0;
    let t = Math.imul(a ^ (a >>> 15), 1 | a);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

function envNumber(name, fallback) {
  const v = (process.env[name] || "").trim();
  if (v === "") return fallback;
  if (!/^(0x[0-9a-fA-F]+|[0-9]+)$/.test(v)) fail(`${name}=${v} is not a number`);
  return BigInt(v);
}

// Text typed into whatever has the keyboard focus (a value box, if a click opened one).
const TYPED = ["0", "-1", "0.5", "1e300", "-1e300", "1e-300", "1.8e308", "NaN", "inf", "-inf",
  "abc", "", "99999999999999999999", "1e"];
const KEYS = ["Tab", "Enter", "Escape", "Space", "ArrowLeft", "ArrowRight", "Home", "End"];
const RANDOM_CONTROLS = ["friction", "time", "section", "exploded", "pin A", "side by side"];

// One random action on the page; returns what it did.
async function randomAction(page, rand, st) {
  const view = rect(st.view, "3D view");
  const below = (y) => Math.max(y, view[1] + 1);
  const anywhere = () => [rand() * VIEWPORT.width, below(rand() * VIEWPORT.height)];
  const inView = () => [view[0] + rand() * view[2], view[1] + rand() * view[3]];
  const r = rand();
  const fmt = (p) => `(${p[0].toFixed(0)}, ${p[1].toFixed(0)})`;
  if (r < 0.3) {
    const controls = JSON.parse(st.controls || "{}");
    const names = RANDOM_CONTROLS.filter((n) => controls[n] && controls[n][2] > 0);
    if (names.length === 0) return "click a control (none reported)";
    const name = names[Math.floor(rand() * names.length)];
    const box = controls[name];
    const frac = rand() < 0.2 ? (rand() < 0.5 ? -0.1 : 1.1) : rand();
    const p = [box[0] + frac * box[2], box[1] + box[3] / 2];
    await page.mouse.click(p[0], below(p[1]));
    return `click "${name}" at ${frac.toFixed(2)} of its width`;
  }
  if (r < 0.5) {
    const p = anywhere();
    if (rand() < 0.15) {
      await page.mouse.dblclick(p[0], p[1]);
      return `double-click at ${fmt(p)}`;
    }
    await page.mouse.click(p[0], p[1]);
    return `click at ${fmt(p)}`;
  }
  if (r < 0.7) {
    const inside = rand() < 0.5;
    const a = inside ? inView() : anywhere();
    const b = inside ? inView() : anywhere();
    const button = rand() < 0.75 ? "left" : "right";
    await page.mouse.move(a[0], a[1]);
    await page.mouse.down({ button });
    // each event waits for a frame of the page (slow on SwiftShader): few steps
    const steps = 1 + Math.floor(rand() * 2);
    for (let k = 1; k <= steps; k++) {
      await page.mouse.move(a[0] + ((b[0] - a[0]) * k) / steps, a[1] + ((b[1] - a[1]) * k) / steps);
    }
    await page.mouse.up({ button });
    return `${button} drag from ${fmt(a)} to ${fmt(b)}`;
  }
  if (r < 0.78) {
    const p = anywhere();
    const dy = (rand() - 0.5) * 2000;
    await page.mouse.move(p[0], p[1]);
    await page.mouse.wheel(0, dy);
    return `wheel ${dy.toFixed(0)} at ${fmt(p)}`;
  }
  if (r < 0.86) {
    const text = TYPED[Math.floor(rand() * TYPED.length)];
    const key = KEYS[Math.floor(rand() * 3)];
    await page.keyboard.insertText(text);
    await page.keyboard.press(key);
    return `type "${text}", then ${key}`;
  }
  if (r < 0.9) {
    const key = KEYS[Math.floor(rand() * KEYS.length)];
    await page.keyboard.press(key);
    return `key ${key}`;
  }
  const ms = Math.floor(50 + rand() * 550);
  await page.waitForTimeout(ms);
  return `wait ${ms} ms`;
}

// The page after an action: it answers, nothing failed.
function checkRandomState(st, errors) {
  failOnErrors(errors);
  if (st.state === "failed" && /non-finite value during the solve|^probe:/.test(st.error || "")) {
    fail(`the solve failed: ${st.error}`);
  }
  if (st.state === "not-converged") fail(`a solve ended unconverged: ${st.title}`);
}

async function randomMain() {
  fs.mkdirSync(outDir, { recursive: true });
  const seed = envNumber("LOPIN_UI_SEED", 20240917n);
  const clicks = Number(envNumber("LOPIN_UI_CLICKS", 300n));
  const seconds = Number(envNumber("LOPIN_UI_SECONDS", 90n));
  const rand = generator(seed);
  const errors = [];
  const actions = [];
  const report = { url, seed: seed.toString(), clicks, seconds, actions, screenshots: [] };
  const browser = await launch();
  try {
    const page = await openPage(browser, errors);
    await page.goto(url, { waitUntil: "load" });
    let st = await waitConverged(page, 1, LOAD_TIMEOUT_MS);
    const t0 = Date.now();
    for (let i = 0; i < clicks && Date.now() - t0 < seconds * 1000; i++) {
      const a0 = Date.now();
      const what = await randomAction(page, rand, st);
      actions.push(`${what} (${Date.now() - a0} ms)`);
      // the page answers within the action's timeout (a hung page throws here)
      st = await status(page);
      checkRandomState(st, errors);
      if (i % 50 === 49) {
        const s = await checkDrawn(page, path.join(outDir, "web-random.png"), rect(st.view, "3D view"));
        delete s.png;
        report.screenshots.push(s);
      }
    }
    report.seconds_used = (Date.now() - t0) / 1000;
    // the newest request ends: converged, or a value the solver refuses
    await page.waitForFunction(
      () => !["solving", "starting"].includes(document.getElementById("lopin-status").dataset.state),
      null,
      { timeout: RESOLVE_TIMEOUT_MS, polling: 50 }
    );
    await page.waitForTimeout(300);
    st = await status(page);
    checkRandomState(st, errors);
    report.end = { state: st.state, title: st.title, error: st.error || "" };
    const s = await checkDrawn(page, path.join(outDir, "web-random.png"), rect(st.view, "3D view"));
    delete s.png;
    report.screenshots.push(s);
  } catch (e) {
    const from = Math.max(0, actions.length - 30);
    const last = actions.slice(from).map((a, k) => `  ${from + k}: ${a}`);
    e.message +=
      `\nLOPIN_UI_SEED=${seed} LOPIN_UI_CLICKS=${clicks} LOPIN_UI_SECONDS=${seconds} ` +
      `(action ${actions.length})\nlast actions:\n${last.join("\n")}`;
    throw e;
  } finally {
    await browser.close();
    report.console_errors = errors;
    fs.writeFileSync(path.join(outDir, "web-random.json"), JSON.stringify(report, null, 2));
  }
  failOnErrors(errors);
  return report;
}

if (randomMode) {
  randomMain().then(
    (r) =>
      console.log(
        `web random use: seed ${r.seed}, ${r.actions.length} actions in ` +
          `${r.seconds_used.toFixed(0)} s, ended ${r.end.state}; no console errors`
      ),
    (e) => {
      console.error(`web random use FAILED: ${e.message}`);
      process.exit(1);
    }
  );
} else {
  main().then(
    (r) => {
      const lat = r.moves.map((m) => m.app_latency_s.toFixed(3)).join(", ");
      console.log(
        `web e2e: first frame ${r.first_frame_ms.toFixed(0)} ms, first fields ` +
          `${r.first_fields_ms.toFixed(0)} ms, first converged ${r.first_converged_ms.toFixed(0)} ms ` +
          `after navigation; slider -> converged (s): ${lat}; no console errors`
      );
    },
    (e) => {
      console.error(`web e2e FAILED: ${e.message}`);
      process.exit(1);
    }
  );
}
