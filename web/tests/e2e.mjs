// Browser tests of the dashboard: Debian's Chromium driven by playwright-core against a real
// `fivex serve` on loopback with a fresh database. Run by `.ci/run` (after `npm run build`);
// alone: `npm run build && node tests/e2e.mjs` (FIVEX_BIN picks the binary, default
// ../target/debug/fivex; CHROMIUM the browser, default /usr/bin/chromium).
//
// It saves screenshots in web/test-results/ and prints the page's responsiveness figures
// (measured, never asserted: no timing assertions in tests).
import { chromium } from "playwright-core";
import { execFileSync, spawn } from "node:child_process";
import { mkdtempSync, mkdirSync, readFileSync, rmSync } from "node:fs";
import { createServer } from "node:net";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import assert from "node:assert/strict";

const here = dirname(fileURLToPath(import.meta.url));
const bin = resolve(process.env.FIVEX_BIN ?? join(here, "../../target/debug/fivex"));
const browserPath = process.env.CHROMIUM ?? "/usr/bin/chromium";
const shots = join(here, "../test-results");
mkdirSync(shots, { recursive: true });

const freePort = () =>
  new Promise((ok) => {
    const s = createServer().listen(0, "127.0.0.1", () => {
      const { port } = s.address();
      s.close(() => ok(port));
    });
  });

const port = await freePort();
const base = `http://127.0.0.1:${port}`;
const dir = mkdtempSync(join(tmpdir(), "fivex-e2e-"));
const server = spawn(bin, ["serve", "--db", join(dir, "e2e.db"), "--addr", `127.0.0.1:${port}`], { stdio: ["ignore", "ignore", "pipe"] });
let serverLog = "";
server.stderr.on("data", (d) => (serverLog += d));
const stop = () => {
  server.kill("SIGTERM");
  rmSync(dir, { recursive: true, force: true });
};

async function http(method, path, body, type = "application/json") {
  const res = await fetch(base + path, { method, headers: body != null ? { "content-type": type } : {}, body: body == null ? undefined : type === "application/json" ? JSON.stringify(body) : body });
  const text = await res.text();
  return { status: res.status, body: text ? (res.headers.get("content-type")?.includes("json") ? JSON.parse(text) : text) : null };
}

for (let i = 0; ; i++) {
  try {
    if ((await fetch(base + "/healthz")).ok) break;
  } catch {}
  if (i > 200) throw new Error(`the server did not start:\n${serverLog}`);
  await new Promise((r) => setTimeout(r, 50));
}

const browser = await chromium.launch({
  executablePath: browserPath,
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
const page = await browser.newPage({ viewport: { width: 1500, height: 1100 } });
const problems = [];
page.on("pageerror", (e) => problems.push(`page error: ${e.message}`));
page.on("console", (m) => m.type() === "error" && !/status of 4\d\d/.test(m.text()) && problems.push(`console: ${m.text()}`));
// A dialog is answered with the next of `dialogAnswers` (`false`: dismissed, as "Cancel"),
// else accepted; each is recorded in `dialogsSeen`.
page.on("dialog", (d) => {
  dialogsSeen.push({ type: d.type(), message: d.message() });
  const answer = dialogAnswers.shift();
  return answer === false ? d.dismiss() : d.accept(answer ?? undefined);
});
const dialogAnswers = [];
const dialogsSeen = [];

const tests = [];
const test = (name, fn) => tests.push([name, fn]);
const poll = async (what, fn, ms = 15000) => {
  const until = Date.now() + ms;
  for (;;) {
    const v = await fn();
    if (v) return v;
    if (Date.now() > until) throw new Error(`timed out waiting for ${what}`);
    await page.waitForTimeout(50);
  }
};

/// Whether an element's picture has more than a few colours (a drawn 3D scene, not a blank box).
async function colours(selector) {
  const png = (await page.locator(selector).screenshot()).toString("base64");
  return page.evaluate(async (data) => {
    const img = new Image();
    img.src = `data:image/png;base64,${data}`;
    await img.decode();
    const c = document.createElement("canvas");
    [c.width, c.height] = [img.width, img.height];
    const g = c.getContext("2d");
    g.drawImage(img, 0, 0);
    const px = g.getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < px.length; i += 16) seen.add((px[i] << 16) | (px[i + 1] << 8) | px[i + 2]);
    return seen.size;
  }, png);
}

let id = null;
const PROGRAM = [
  "O0001 (E2E)",
  "G90 G54 G00 X0 Y0 Z50. A0 C0",
  "G01 X40. F3000.",
  "Y40.",
  "X0",
  "Y0",
  "G01 X40. Y40. F3000.",
  "X0 Y0",
  "M30",
].join("\n");

test("the fleet view is empty, then a controller is created from a preset", async () => {
  await page.goto(base + "/");
  await page.getByText("No controllers yet").waitFor();
  await page.fill("form.create input[name=name]", "cell 1");
  await page.selectOption("form.create select[name=preset]", "table-ac");
  await page.click("form.create button[type=submit]");
  await page.waitForURL(/#\/c\//);
  id = decodeURIComponent(page.url().split("#/c/")[1].split("/")[0]);
  await page.locator(".ctl-head h1", { hasText: "cell 1" }).waitFor();
  assert.equal((await http("GET", `/api/v1/controllers/${id}`)).body.machine, "table-ac");
});

test("the 3D view draws the machine", async () => {
  const canvas = page.locator(".view3d canvas");
  await canvas.waitFor({ timeout: 10000 });
  const n = await poll("a drawn canvas", async () => {
    const k = await colours(".view3d canvas");
    return k > 20 ? k : 0;
  });
  assert.ok(n > 20, `the canvas has ${n} colours`);
});

test("a program with a check problem shows its diagnostic in place, then stores and runs", async () => {
  await page.fill(".prog-list .new input", "1");
  await page.click(".prog-list .new button");
  await page.fill("textarea.nc", "G01 X10. F100.\nG65 P\nM30\n");
  await page.click("button[data-action=save]");
  await page.locator("ul.diags li", { hasText: "line 2" }).waitFor();
  await page.fill("textarea.nc", PROGRAM);
  await page.click("button[data-action=save]");
  await page.locator(".code .line[data-line='3']").waitFor();
  assert.equal((await http("GET", `/api/v1/controllers/${id}/programs/1`)).body, PROGRAM);

  const x0 = await page.locator(".pos tr[data-axis=X] td.abs").textContent();
  await page.click("button[data-action=run]");
  await page.locator("[data-run-state=running]").waitFor();
  // The block moving now is highlighted, and it changes as the program runs.
  const first = await poll("a highlighted block", () => page.locator(".code .line.active").getAttribute("data-line", { timeout: 200 }).catch(() => null));
  const later = await poll("the next highlighted block", async () => {
    const l = await page.locator(".code .line.active").getAttribute("data-line", { timeout: 200 }).catch(() => null);
    return l && l !== first ? l : null;
  });
  assert.notEqual(first, later);
  const x1 = await poll("a moving X", async () => {
    const x = await page.locator(".pos tr[data-axis=X] td.abs").textContent();
    return x !== x0 ? x : null;
  });
  assert.notEqual(x0, x1);
  await page.screenshot({ path: join(shots, "controller-running.png") });
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 20000 });
});

// A longer program: 160 mm at 600 mm/min, sixteen seconds.
const LONG = ["O0003 (LONG)", "G90 G54 G00 X0 Y0 Z50. A0 C0", "G01 X40. F600.", "Y40.", "X0", "Y0", "M30"].join("\n");
const textOf = (selector) => page.locator(selector).textContent({ timeout: 200 }).catch(() => "");
/// The camera's distance from what it looks at.
const cameraDistance = () => page.evaluate(() => {
  const v = window.__fivexView.view;
  return v.camera.position.distanceTo(v.controls.target);
});
/// Whether the program column is beside the readout (to its right, overlapping it vertically) and both are in the window.
async function besideReadout(height) {
  const pos = await page.locator(".position").boundingBox();
  const prog = await page.locator(".program-col .code, .program-col textarea.nc").first().boundingBox();
  assert.ok(prog.x >= pos.x + pos.width - 1, `the program (x ${prog.x}) is right of the readout (ends ${pos.x + pos.width})`);
  assert.ok(prog.y < pos.y + pos.height && pos.y < prog.y + prog.height, "they overlap vertically");
  assert.ok(pos.y + pos.height / 2 < height && prog.y + 100 < height, "both are in the window");
}

test("the cycle time is estimated before the start and the time left shown while it runs; another program is edited meanwhile; the layout at 1600×1000 and 1024×700; F fits the part", async () => {
  await page.setViewportSize({ width: 1600, height: 1000 });
  await page.fill(".prog-list .new input", "3");
  await page.click(".prog-list .new button");
  await page.fill("textarea.nc", LONG);
  await page.click("button[data-action=save]");
  await page.locator(".code .line[data-line='6']").waitFor();
  const estimate = (await http("GET", `/api/v1/controllers/${id}/programs/3/estimate`)).body;
  const shown = await poll("the estimate", async () => {
    const t = await textOf("[data-testid=cycle-time]");
    return /cycle time \d+:\d\d\.\d/.test(t) ? t : null;
  });
  if (estimate.state === "ready") assert.ok(estimate.cycle_time_s > 16 && estimate.cycle_time_s < 18, JSON.stringify(estimate));
  await page.click("button[data-action=run]");
  await page.locator("[data-run-state=running]").waitFor();
  const left = await poll("the time left", async () => {
    const t = await textOf("[data-testid=cycle-time]");
    return /elapsed · \d+:\d\d\.\d left · \d+ %/.test(t) ? t : null;
  });
  assert.match(shown, /cycle time/);
  assert.ok(await page.locator("[data-testid=cycle-time] [role=progressbar]").count(), `a bar with ${left}`);
  await besideReadout(1000);
  await page.locator(".program-col .code .line.active").waitFor();
  await page.screenshot({ path: join(shots, "controller-1600x1000.png") });

  // Background edit: a new program stored while O0003 runs, which goes on.
  await page.fill(".prog-list .new input", "4");
  await page.click(".prog-list .new button");
  const other = "O0004 (EDITED WHILE 3 RUNS)\nG01 X5. F100.\nM30\n";
  await page.fill("textarea.nc", other);
  await page.click("button[data-action=save]");
  await poll("O0004 stored", async () => (await http("GET", `/api/v1/controllers/${id}/programs/4`)).body === other);
  const during = (await http("GET", `/api/v1/controllers/${id}`)).body;
  assert.equal(during.run_state, "running");
  assert.equal(during.program, 3);
  assert.ok(during.progress.elapsed_s > 0 && during.progress.estimate.state === "ready", JSON.stringify(during.progress));

  await page.setViewportSize({ width: 1024, height: 700 });
  await page.click("[data-program='3']");
  await page.locator(".program-col .code .line.active").waitFor();
  await besideReadout(700);
  await page.screenshot({ path: join(shots, "controller-1024x700.png") });

  // F frames the part (path, trace, work zero): much closer than the whole machine.
  await page.click("button[title='Frame the machine']");
  const machine = await cameraDistance();
  await page.click(".ctl-head h1");
  await page.keyboard.press("f");
  const part = await poll("the view on the part", async () => {
    const d = await cameraDistance();
    return d < machine * 0.6 ? d : null;
  });
  assert.ok(part < machine, `${part} < ${machine}`);
  assert.ok(await page.evaluate(() => window.__fivexView.view.machineScene.workZero.object.visible), "the work zero is drawn");
  await page.locator(".view3d").screenshot({ path: join(shots, "fit-part.png") });
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 30000 });
  await page.setViewportSize({ width: 1500, height: 1100 });
});

test("program restart: the dialog searches to a line, the program area shows it, cycle start returns and finishes", async () => {
  // P type after the run above, restarting at line 5 ("X0" after X40. Y40.).
  await page.click("button[data-action=restart]");
  const dialog = page.locator(".restart-dialog");
  await dialog.waitFor();
  await dialog.locator("select").nth(1).selectOption("line");
  await dialog.locator("input[name=restart-block]").fill("5");
  await page.screenshot({ path: join(shots, "restart-dialog.png") });
  await page.click("button[data-action=restart-search]");
  const info = page.locator(".restart-info[data-restart=searched]");
  await info.waitFor();
  assert.match(await info.textContent(), /P type restart at \(line 5\).*to X40\.000 Y40\.000 Z50\.000/);
  await dialog.waitFor({ state: "detached" });
  const searched = (await http("GET", `/api/v1/controllers/${id}`)).body;
  assert.equal(searched.restart.line, 5);
  assert.equal(searched.run_state, "idle");
  await page.screenshot({ path: join(shots, "restart-searched.png") });
  await page.click(".op-panel button[title='cycle start']");
  await info.waitFor({ state: "detached", timeout: 20000 });
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 20000 });
  const done = await poll("the program's end", async () => {
    const s = (await http("GET", `/api/v1/controllers/${id}`)).body;
    return s.run_state === "idle" && s.restart === null ? s : null;
  });
  assert.deepEqual(done.alarms, []);
  assert.equal(done.position.workpiece.X, 0);
  assert.equal(done.position.workpiece.Y, 0);
});

test("an alarm shows in the banner and in the alarms tab", async () => {
  await page.click("nav.tabs a[href$='/mdi']");
  await page.fill("textarea[name=mdi]", "M98 P9999"); // no such program
  await page.click(".mdi button[type=submit]");
  const banner = page.locator(".alarm-banner");
  await banner.waitFor();
  const code = (await http("GET", `/api/v1/controllers/${id}`)).body.alarms[0].code;
  assert.match(await banner.textContent(), new RegExp(code));
  await page.click("nav.tabs a[href$='/alarms']");
  await page.locator(".active-alarms li", { hasText: code }).waitFor();
  await page.screenshot({ path: join(shots, "controller-alarm.png") });
  await page.click(".op-panel button[title=reset]");
  await banner.waitFor({ state: "detached" });
});

test("the panel's switches: machine lock runs the program with the machine standing, dry run, the spindle override, the counters", async () => {
  const status = async () => (await http("GET", `/api/v1/controllers/${id}`)).body;
  for (const k of ["machine_lock", "dry_run"]) {
    await page.click(`.op-panel button[data-switch=${k}]`);
    await poll(`${k} on`, async () => (await page.locator(`.op-panel button[data-switch=${k}]`).getAttribute("aria-pressed")) === "true");
    assert.equal((await status()).panel[k], true);
  }
  await page.selectOption(".op-panel select[title='spindle override']", "80");
  await poll("the spindle override", async () => (await status()).panel.spindle_override === 80);
  const parts = (await status()).counters.parts;
  // Dry run without a dry run rate (No.1410) feeds at the jog feed: a quick one.
  const jogFeed = (await status()).panel.jog_feed;
  await http("PUT", `/api/v1/controllers/${id}/manual`, { jog_feed: 6000 });
  assert.equal((await http("POST", `/api/v1/controllers/${id}/cycle-start`, { program: 1 })).status, 200);
  await page.locator("[data-run-state=running]").waitFor();
  // The workpiece position moves, the machine position stays (0 on X at the start: G90 X0).
  const x0 = await page.locator(".pos tr[data-axis=X] td.mach").textContent();
  await poll("a moving workpiece X", async () => {
    const abs = await page.locator(".pos tr[data-axis=X] td.abs").textContent();
    return Number(abs) > 1 ? abs : null;
  });
  assert.equal(await page.locator(".pos tr[data-axis=X] td.mach").textContent(), x0);
  // A switch that changes only at rest is refused while the program runs, with the reason shown.
  await page.click(".op-panel button[data-switch=dry_run]");
  await page.locator("p.error", { hasText: /runs/ }).waitFor();
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 30000 });
  await page.locator(".op-panel .counters", { hasText: `parts ${parts + 1}` }).waitFor();
  await page.locator(".op-panel").screenshot({ path: join(shots, "panel-switches.png") });
  // Back: the switches off, the reference return sets the coordinates to the machine again.
  for (const k of ["machine_lock", "dry_run"]) await page.click(`.op-panel button[data-switch=${k}]`);
  await poll("the switches off", async () => {
    const p = (await status()).panel;
    return !p.machine_lock && !p.dry_run;
  });
  await http("PUT", `/api/v1/controllers/${id}/mode`, { mode: "ref" });
  await http("POST", `/api/v1/controllers/${id}/reference-return`, {});
  await poll("the coordinates agree", async () => {
    const s = await status();
    return s.run_state === "idle" && Object.values(s.lock_offset).every((v) => v === 0);
  });
  await http("PUT", `/api/v1/controllers/${id}/mode`, { mode: "auto" });
  await http("PUT", `/api/v1/controllers/${id}/overrides`, { spindle: 100 });
  await http("PUT", `/api/v1/controllers/${id}/manual`, { jog_feed: jogFeed });
});

test("a macro variable is edited in the table", async () => {
  await page.click("nav.tabs a[href$='/variables']");
  await page.fill("input[name=var-number]", "#500");
  dialogAnswers.push("12.5");
  await page.click(".variables button:has-text('set')");
  const cell = page.locator("tr[data-var='500'] input");
  await poll("#500 in the table", async () => (await cell.count()) && (await cell.inputValue()) === "12.5");
  await cell.fill("7.25");
  await cell.press("Enter");
  await poll("#500 = 7.25 in the service", async () => (await http("GET", `/api/v1/controllers/${id}/variables/500`)).body.value === 7.25);
});

test("a tool offset's corner radius is edited in the offsets table; a negative one is refused", async () => {
  await page.click("nav.tabs a[href$='/offsets']");
  const cell = page.locator("tr[data-tool='3'] td[data-field=corner_radius] input");
  await poll("offset 3's Corner R", async () => (await cell.count()) && (await cell.inputValue()) === "0");
  assert.ok((await page.locator(".offsets thead th").allTextContents()).includes("Corner R"));
  await cell.fill("1.5");
  await cell.press("Enter");
  const three = async () => (await http("GET", `/api/v1/controllers/${id}/tool-offsets`)).body.find((t) => t.number === 3);
  await poll("corner radius 1.5 in the service", async () => (await three())?.corner_radius === 1.5);
  assert.equal((await three()).radius, 5, "the D radius is kept");
  await page.screenshot({ path: join(shots, "controller-offsets.png") });
  await cell.fill("-1");
  await cell.press("Enter");
  await page.locator("p.error", { hasText: "corner_radius" }).waitFor();
  assert.equal((await three()).corner_radius, 1.5, "the refused value changed nothing");
  await page.click("p.error");
});

test("the fleet view shows the controllers live, with clone and delete", async () => {
  await http("POST", "/api/v1/controllers", { name: "head 1", preset: "head-bc" });
  await http("POST", "/api/v1/controllers", { name: "mixed 1", preset: "mixed-bc", dialect: "syntec" });
  await page.goto(base + "/#/");
  await page.locator(`tr[data-id='${id}']`).waitFor();
  dialogAnswers.push("cell 1 copy");
  await page.click(`tr[data-id='${id}'] button[title=clone]`);
  await page.locator(".fleet-table a.name", { hasText: "cell 1 copy" }).waitFor();
  // A state change elsewhere shows without reloading.
  const other = (await http("GET", "/api/v1/controllers")).body.find((c) => c.name === "head 1");
  await http("POST", `/api/v1/controllers/${other.id}/mdi`, { text: "G01 X1." });
  await page.locator(`tr[data-id='${other.id}'] .state.alarm`).waitFor();
  await page.screenshot({ path: join(shots, "fleet.png") });
  const copy = (await http("GET", "/api/v1/controllers")).body.find((c) => c.name === "cell 1 copy");
  await page.click(`tr[data-id='${copy.id}'] button[title=delete]`);
  await page.locator(`tr[data-id='${copy.id}']`).waitFor({ state: "detached" });
  assert.equal((await http("GET", `/api/v1/controllers/${copy.id}`)).status, 404);
});

test("every preset kind draws in the 3D view", async () => {
  for (const preset of ["mill3", "head-bc", "table-bc", "mixed-bc"]) {
    const c = (await http("POST", "/api/v1/controllers", { name: `view ${preset}`, preset })).body;
    await page.goto(`${base}/#/c/${c.id}`);
    await page.locator(".view3d canvas").waitFor();
    const n = await poll(`a drawn ${preset}`, async () => {
      const k = await colours(".view3d canvas");
      return k > 20 ? k : 0;
    });
    assert.ok(n > 20);
    await page.screenshot({ path: join(shots, `machine-${preset}.png`) });
  }
  // The Haas machines of the library (Haas settings lists: travels below machine zero, the
  // trunnions' axes through the MRZP) draw too.
  for (const name of ["haas-umc-750", "haas-vf2-tr160", "haas-vf2-hrt160"]) {
    const { machine } = (await http("GET", `/api/v1/fleet/library/${name}`)).body;
    const c = (await http("POST", "/api/v1/controllers", { name: `view ${name}`, machine })).body;
    await page.goto(`${base}/#/c/${c.id}`);
    await page.locator(".view3d canvas").waitFor();
    const n = await poll(`a drawn ${name}`, async () => {
      const k = await colours(".view3d canvas");
      return k > 20 ? k : 0;
    });
    assert.ok(n > 20);
    await page.screenshot({ path: join(shots, `machine-${name}.png`) });
  }
});

test("a fleet run compares machines, shows why one cannot run it, and opens one in 3D", async () => {
  await page.goto(base + "/#/runs");
  await page.fill("textarea[name=program]", ["O1000", "G90 G00 X0 Y0 Z100. B0 C0", "G43.4 H1", "G01 X20. Y10. Z20. B20. C30. F2000.", "X-20. B-10. C60.", "G49", "M30"].join("\n"));
  for (const key of ["preset:head-bc", "preset:mill3", "preset:mixed-bc", "library:fork-head-bc"]) await page.check(`input[data-pick='${key}']`);
  await page.click("form.new-run button[type=submit]");
  await page.waitForURL(/#\/runs\/./);
  const table = page.locator("table.compare");
  await table.waitFor({ timeout: 60000 });
  assert.equal(await table.locator("tbody tr").count(), 4);
  // mill3 has no B and C: the program's alarm, code and line, is in its row.
  assert.match(await table.locator("tr[data-machine='mill3'] td").first().textContent(), /PS\d{4}.*line 2/);
  assert.match(await table.locator("tr[data-machine='head-bc'] td").first().textContent(), /completed/);
  await page.locator("svg.plot.bars rect").first().waitFor();
  await page.locator("svg.plot.lines polyline").first().waitFor();
  await page.screenshot({ path: join(shots, "fleet-run.png"), fullPage: true });
  await table.locator("tr[data-machine='head-bc'] button").click();
  await page.waitForURL(/#\/c\//);
  await page.locator(".view3d canvas").waitFor();
  await page.locator("[data-run-state=running]").waitFor();
  const runs = (await http("GET", "/api/v1/fleet/runs")).body;
  assert.equal(runs[0].machines, 4);
  assert.equal(runs[0].alarms, 1);
});

test("with --token the page asks for it at the first 401, sends it again, and streams with it percent-encoded", async () => {
  const TOKEN = "a+b/c=d"; // + / = : what base64 tokens hold
  const tport = await freePort();
  const tbase = `http://127.0.0.1:${tport}`;
  const tdir = mkdtempSync(join(tmpdir(), "fivex-e2e-token-"));
  const tserver = spawn(bin, ["serve", "--db", join(tdir, "t.db"), "--addr", `127.0.0.1:${tport}`, "--token", TOKEN], { stdio: "ignore" });
  const tpage = await browser.newPage({ viewport: { width: 1500, height: 1100 } });
  const seen = [];
  tpage.on("pageerror", (e) => problems.push(`token page error: ${e.message}`));
  // Refused requests and websocket handshakes are what this test makes happen.
  const refused = /status of 401|WebSocket connection to .* failed: (.*401|HTTP Authentication failed)/;
  tpage.on("console", (m) => m.type() === "error" && !refused.test(m.text()) && problems.push(`token page console: ${m.text()}`));
  tpage.on("websocket", (ws) => seen.push(ws.url()));
  try {
    for (let i = 0; !(await fetch(tbase + "/healthz").then((r) => r.ok, () => false)); i++) {
      if (i > 200) throw new Error("the server with a token did not start");
      await new Promise((r) => setTimeout(r, 50));
    }
    const auth = { authorization: `Bearer ${TOKEN}`, "content-type": "application/json" };
    const c = await (await fetch(tbase + "/api/v1/controllers", { method: "POST", headers: auth, body: JSON.stringify({ name: "locked", preset: "mill3" }) })).json();

    await tpage.goto(tbase + "/");
    const form = tpage.locator("form.login");
    await form.waitFor();
    await form.locator("input[name=token]").fill("wrong");
    await form.locator("button[type=submit]").click();
    await tpage.locator("form.login", { hasText: "refused that token" }).waitFor();
    await form.locator("input[name=token]").fill(TOKEN);
    await tpage.screenshot({ path: join(shots, "login.png") });
    await form.locator("button[type=submit]").click();
    await form.waitFor({ state: "detached" });
    // The fleet websocket works with the token, percent-encoded.
    await tpage.locator(`tr[data-id='${c.id}']`).waitFor();
    await tpage.locator(".pill.live").waitFor();
    assert.ok(seen.some((u) => u.includes("token=a%2Bb%2Fc%3Dd")), seen.join(" "));
    assert.equal(await tpage.evaluate(() => localStorage.getItem("fivex.token")), TOKEN);
    // The controller view: its status over REST, its live state over its websocket.
    await tpage.goto(`${tbase}/#/c/${c.id}`);
    await tpage.locator(".ctl-head h1", { hasText: "locked" }).waitFor();
    await tpage.locator("[data-run-state=idle]").waitFor();
    await fetch(`${tbase}/api/v1/controllers/${c.id}/mdi`, { method: "POST", headers: auth, body: JSON.stringify({ text: "G91 G01 X50. F100." }) });
    await tpage.locator("[data-run-state=running]").waitFor();
    // A token the service no longer takes: asked for again, as refused.
    await tpage.evaluate(() => localStorage.setItem("fivex.token", "stale"));
    await tpage.reload();
    await tpage.locator("form.login", { hasText: "refused that token" }).waitFor();
    await tpage.locator("form.login input[name=token]").fill(TOKEN);
    await tpage.locator("form.login button[type=submit]").click();
    await tpage.locator(".ctl-head h1", { hasText: "locked" }).waitFor();
    await tpage.locator("button[data-action=sign-out]").waitFor();
  } finally {
    await tpage.close();
    tserver.kill("SIGTERM");
    rmSync(tdir, { recursive: true, force: true });
  }
});

test("Swagger UI offers Authorize (the document's bearer scheme)", async () => {
  await page.goto(base + "/swagger-ui/");
  await page.locator("button.authorize").waitFor();
  await page.click("button.authorize");
  await page.locator(".auth-container", { hasText: "bearer" }).waitFor();
  await page.screenshot({ path: join(shots, "swagger-authorize.png") });
});

test("a fleet run that never ends is cancelled from the dashboard; the one queued behind it then runs", async () => {
  const endless = ["O1", "#1=0", "WHILE[#1 GE 0]DO1", "#1=#1+1", "END1", "M30"].join("\n");
  const running = (await http("POST", "/api/v1/fleet/runs?wait=false", { program: endless, presets: ["mill3"] })).body;
  const queued = (await http("POST", "/api/v1/fleet/runs?wait=false", { program: "O2\nG91 G01 X5. F1000\nM30", presets: ["mill3"] })).body;
  await page.goto(`${base}/#/runs`);
  await page.locator(`tr[data-run='${queued.id}'] .run-status.queued`).waitFor();
  await page.goto(`${base}/#/runs/${running.id}`);
  await page.locator("[data-run-status=running]").waitFor();
  await page.click("button.cancel-run");
  await page.locator("[data-run-status=cancelled]").waitFor({ timeout: 10000 });
  assert.equal((await http("GET", `/api/v1/fleet/runs/${running.id}`)).body.status, "cancelled");
  await poll("the queued run done", async () => (await http("GET", `/api/v1/fleet/runs/${queued.id}`)).body.status === "done");
});

test("under cutter compensation the 3D view draws the programmed path dashed beside the tool centre path, with a legend", async () => {
  const made = await http("POST", "/api/v1/controllers", { name: "crc", preset: "mill3" });
  assert.equal(made.status, 201, JSON.stringify(made.body));
  const cid = made.body.id;
  const square = "O0002\nG21 G17 G40 G90\nG00 X-20. Y-20.\nG41 D1 G01 X0. Y0. F500.\nY40.\nX40.\nY0.\nX0.\nG40 X-20. Y-20.\nM30\n";
  assert.ok((await http("PUT", `/api/v1/controllers/${cid}/programs/2`, square, "text/plain")).status < 300);
  assert.ok((await http("PUT", `/api/v1/controllers/${cid}/programs/3`, "O0003\nG90 G00 X10. Y10.\nG01 X30. F500.\nM30\n", "text/plain")).status < 300);
  await page.goto(`${base}/#/c/${cid}/program`);
  await page.locator(".view3d canvas").waitFor();
  await page.click(".prog-list a[data-program='2']");
  const legend = page.locator("[data-testid=path-legend]");
  await legend.waitFor();
  const text = await legend.textContent();
  assert.match(text, /tool centre path/);
  assert.match(text, /programmed path/);
  const drawn = await poll("the programmed path in the scene", () =>
    page.evaluate(() => {
      const s = window.__fivexView?.view.machineScene;
      return s && s.programmed.segments > 0 && s.path.object.geometry.getAttribute("position") ? { programmed: s.programmed.segments, centre: s.path.object.geometry.getAttribute("position").count / 2, dashed: s.programmed.object.material.type } : null;
    }),
  );
  assert.equal(drawn.dashed, "LineDashedMaterial");
  assert.ok(drawn.programmed >= 7 && drawn.centre >= 7, JSON.stringify(drawn));
  await page.screenshot({ path: join(shots, "path-compensated.png") });
  // A program without compensation: one path, no legend.
  await page.click(".prog-list a[data-program='3']");
  await legend.waitFor({ state: "detached" });
  // The view drops the programmed path on its next update, which may come after the legend goes.
  await poll("the programmed path gone", () =>
    page.evaluate(() => window.__fivexView.view.machineScene.programmed.segments === 0),
  );
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

test("under cutting point control (G43.8) the 3D view draws the cutting point's trace beside the tip trace", async () => {
  const made = await http("POST", "/api/v1/controllers", { name: "cutting point", preset: "head-bc" });
  assert.equal(made.status, 201, JSON.stringify(made.body));
  const cid = made.body.id;
  // A bull-nose end mill: radius 5, corner radius 1.
  const put = await http("PUT", `/api/v1/controllers/${cid}/tool-offsets/1`, { length: 100, radius: 5, corner_radius: 1 });
  assert.ok(put.status < 300, JSON.stringify(put.body));
  const program = "O0004\nG90 G00 X0 Y0 Z100. B0 C0\nG43.8 H1 D1 ,L2 I1.\nG01 Y20. Z10. F2000.\nG49\nG00 Z250.\nM30\n";
  const stored = await http("PUT", `/api/v1/controllers/${cid}/programs/4`, program, "text/plain");
  assert.ok(stored.status < 300, JSON.stringify(stored.body));
  await page.goto(`${base}/#/c/${cid}/program`);
  await page.locator(".view3d canvas").waitFor();
  await page.click(".prog-list a[data-program='4']");
  await page.locator(".pill.live").waitFor();
  const traced = () =>
    page.evaluate(() => {
      const s = window.__fivexView?.view.machineScene;
      return s ? { tip: s.trace.length, cutting: s.cutting.length, stretches: s.cutting.lines.length, marker: s.cuttingMarker.visible } : null;
    });
  const before = await poll("the 3D view", traced);
  assert.deepEqual({ ...before, tip: 0 }, { tip: 0, cutting: 0, stretches: 0, marker: false });
  await page.click("button[data-action=run]");
  await page.locator("[data-run-state=running]").waitFor();
  await poll("the cutting point's marker", async () => (await traced())?.marker);
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 30000 });
  const after = await traced();
  assert.ok(after.cutting >= 5 && after.tip > after.cutting, JSON.stringify(after));
  // One G43.8 move: one stretch (the rapid away after G49 adds none); the marker hid when it ended.
  assert.equal(after.stretches, 1, JSON.stringify(after));
  assert.equal(after.marker, false);
  // The surface normal is +X (I1.) and the tool vertical, so the tool touches it on its side, 5 mm
  // (the radius) in −X and 1 mm (the corner radius) above its tip: the cutting points at the
  // programmed X0 along Y0 Z100 → Y20 Z10, the tip at X5.
  const points = await page.evaluate(() => {
    const line = window.__fivexView.view.machineScene.cutting.lines[0];
    return Array.from({ length: line.length }, (_, i) => line.point(i));
  });
  for (const [x, y, z] of points) {
    assert.ok(Math.abs(x) < 1e-3, `cutting point X ${x}`);
    assert.ok(y > -1e-3 && y < 20 + 1e-3 && z > 10 - 1e-3 && z < 100 + 1e-3, `cutting point ${[x, y, z]}`);
  }
  assert.ok(points.at(-1)[1] > 15, `the last cutting point ${points.at(-1)}`);
  // A close look for the screenshot (the head is up, out of the way), at the middle of the
  // cutting trace, from the −X side: the tip trace runs 5 mm behind it.
  await page.evaluate(() => {
    const v = window.__fivexView.view;
    const line = v.machineScene.cutting.lines[0];
    const at = line.object.localToWorld(v.controls.target.clone().set(...line.point(Math.floor(line.length / 2))));
    v.controls.target.copy(at);
    v.camera.position.copy(at).add(at.clone().set(-160, -90, 40));
    v.controls.update();
    v.render();
  });
  await page.locator(".view3d").screenshot({ path: join(shots, "cutting-point-trace.png") });
  // clear trace clears both traces.
  await page.click(".view3d button[title^='Clear the tool-tip trace']");
  assert.deepEqual(await traced(), { tip: 0, cutting: 0, stretches: 0, marker: false });
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

test("while a tilted working plane is in force the 3D view draws its frame on the part, and none after G69", async () => {
  const made = await http("POST", "/api/v1/controllers", { name: "tilted plane", preset: "table-ac" });
  assert.equal(made.status, 201, JSON.stringify(made.body));
  const cid = made.body.id;
  // G68.2 Euler ZXZ I0 J30. K0: the feature system's Z tilted 30° about X, its origin X20. Y10.
  const program = "O0005\nG90 G54 G00 X0 Y0 Z100. A0 C0\nG68.2 X20. Y10. Z0 I0 J30. K0\nG53.1\nG01 X30. Y20. Z20. F3000.\nM00\nG69\nG00 Z150.\nM30\n";
  const stored = await http("PUT", `/api/v1/controllers/${cid}/programs/5`, program, "text/plain");
  assert.ok(stored.status < 300, JSON.stringify(stored.body));
  await page.goto(`${base}/#/c/${cid}/program`);
  await page.locator(".view3d canvas").waitFor();
  await page.click(".prog-list a[data-program='5']");
  await page.locator(".pill.live").waitFor();
  const plane = () =>
    page.evaluate(() => {
      const s = window.__fivexView?.view.machineScene;
      if (!s) return null;
      s.rig.root.updateMatrixWorld(true);
      const o = s.workingPlane.object;
      const origin = o.getWorldPosition(o.position.clone());
      // The plane's Z axis in world coordinates (the rotation only).
      const z = o.position.clone().set(0, 0, 1).transformDirection(o.matrixWorld);
      return { visible: o.visible, origin: origin.toArray(), z: z.toArray(), tableZ: s.rig.tableFrame.position.clone().set(0, 0, 1).transformDirection(s.rig.tableFrame.matrixWorld).toArray() };
    });
  assert.equal((await poll("the 3D view", plane)).visible, false, "no plane before the program");
  await page.click("button[data-action=run]");
  const stopped = await poll("the M00 stop under the plane", async () => {
    const st = (await http("GET", `/api/v1/controllers/${cid}`)).body;
    return st.run_state !== "running" && st.line === 6 ? st : null;
  });
  assert.ok(stopped.alarms.length === 0, JSON.stringify(stopped.alarms));
  const drawn = await poll("the plane's frame", async () => ((await plane())?.visible ? plane() : null));
  // G53.1 turned A so that the plane's Z is the tool axis (machine +Z).
  assert.ok(Math.abs(drawn.z[2] - 1) < 1e-6, `the plane's Z in the machine: ${drawn.z}`);
  assert.ok(Math.abs(drawn.tableZ[2] - Math.cos(Math.PI / 6)) < 1e-6, `the table turned 30°: ${drawn.tableZ}`);
  await page.keyboard.press("Escape");
  await page.click(".ctl-head h1");
  await page.keyboard.press("f");
  await page.waitForTimeout(300);
  await page.locator(".view3d").screenshot({ path: join(shots, "tilted-plane.png") });
  await page.click(".op-panel button[title='cycle start']");
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 30000 });
  await poll("the plane's frame hidden after G69", async () => ((await plane())?.visible === false ? true : null));
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

test("after G10 L5000 P2 the 3D view turns the exchanged head's axes (set 2 of head-exchange-bc-ac), and set 1's after P1", async () => {
  const file = join(here, "../../machines/head-exchange-bc-ac.json");
  const made = await http("POST", "/api/v1/controllers", { name: "head exchange", dialect: "syntec", machine: JSON.parse(readFileSync(file, "utf8")) });
  assert.equal(made.status, 201, JSON.stringify(made.body));
  const cid = made.body.id;
  await page.goto(`${base}/#/c/${cid}/mdi`);
  await page.locator(".view3d canvas").waitFor();
  // What the page draws: the chain, its joints, the axes and tool length it was given, the tool
  // tip marker's world position and the drawn tool's direction (tip → holder).
  const drawn = () =>
    page.evaluate(() => {
      const s = window.__fivexView?.view.machineScene;
      if (!s) return null;
      const tool = s.rig.root.getObjectByName("tool");
      const holder = tool.localToWorld(tool.position.clone().set(0, 0, 0));
      const end = tool.localToWorld(tool.position.clone().set(0, 1, 0));
      const dir = holder.sub(end).normalize();
      const tip = s.rig.tip.getWorldPosition(tool.position.clone());
      return { chain: s.chain, joints: [...s.rig.joints.keys()].sort(), axes: s.getAxes(), L: s.getToolLength(), tip: tip.toArray(), tool: dir.toArray(), trace: s.trace.length, traceOnTable: s.trace.object.parent === s.rig.tableFrame };
    });
  // The engine's forward kinematics of the drawn axes in a chain (`fivex kin fk --chain`).
  const fk = (d, chain) => {
    const axes = Object.entries(d.axes).map(([k, v]) => `${k}=${v}`).join(",");
    return JSON.parse(execFileSync(bin, ["kin", "fk", "--machine", file, "--chain", chain, "--axes", axes, "--tool-length", String(d.L)], { encoding: "utf8" }));
  };
  const near = (a, b, tol) => a.every((x, i) => Math.abs(x - b[i]) <= tol);
  const mdi = async (text) => {
    await page.fill("textarea[name=mdi]", text);
    await page.click(".mdi button[type=submit]");
  };
  const before = await poll("the 3D view", drawn);
  assert.deepEqual(before.chain, { set: 1, sub: 1 });
  assert.deepEqual(before.joints, ["B", "C"]);

  await mdi("G10 L5000 P2\nG90 G00 X40. Y-30. A30. B-20. C40.");
  const set2 = await poll("set 2 drawn at A30 C40", async () => {
    const d = await drawn();
    return d?.chain.set === 2 && d.axes.A === 30 && d.axes.C === 40 && d.axes.X === 40 ? d : null;
  });
  assert.deepEqual(set2.joints, ["A", "C"]);
  const want2 = fk(set2, "2");
  assert.ok(near(set2.tool, want2.tool_machine, 1e-6), `drawn tool ${set2.tool}, set 2's ${want2.tool_machine}`);
  assert.ok(near(set2.tip, want2.tip_machine, 1e-6), `drawn tip ${set2.tip}, set 2's ${want2.tip_machine}`);
  // Set 1 (B about Y) would point the tool elsewhere: the check tells the heads apart.
  const other = fk(set2, "1");
  assert.ok(!near(set2.tool, other.tool_machine, 0.1), `set 1's tool ${other.tool_machine} is as drawn`);
  // The tip trace followed the move and stays on the table frame of the rebuilt rig.
  assert.ok(set2.trace > 0 && set2.traceOnTable, JSON.stringify(set2));
  await page.locator(".view3d").screenshot({ path: join(shots, "chain-set2.png") });

  await mdi("G10 L5000 P1");
  const set1 = await poll("set 1 drawn again", async () => {
    const d = await drawn();
    return d?.chain.set === 1 ? d : null;
  });
  assert.deepEqual(set1.joints, ["B", "C"]);
  const want1 = fk(set1, "1");
  assert.ok(near(set1.tool, want1.tool_machine, 1e-6), `drawn tool ${set1.tool}, set 1's ${want1.tool_machine}`);
  assert.ok(near(set1.tip, want1.tip_machine, 1e-6), `drawn tip ${set1.tip}, set 1's ${want1.tip_machine}`);
  // The trace is kept through the rebuild (the other head's tip is elsewhere: at most one point more).
  assert.ok(set1.trace >= set2.trace && set1.trace <= set2.trace + 1 && set1.traceOnTable, JSON.stringify(set1));
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

test("the Teach panel of a Syntec controller latches three points, teaches the G68.2 block and sets the plane (F2)", async () => {
  const fanuc = (await http("POST", "/api/v1/controllers", { name: "teach fanuc", preset: "head-bc" })).body.id;
  await page.goto(`${base}/#/c/${fanuc}`);
  await page.locator(".ctl-head h1", { hasText: "teach fanuc" }).waitFor();
  assert.equal(await page.locator(".teach").count(), 0, "no Teach panel on a FANUC controller");
  const s = (await http("POST", "/api/v1/controllers", { name: "teach syntec", preset: "head-bc", dialect: "syntec", speed: 20 })).body.id;
  await http("PUT", `/api/v1/controllers/${s}/tool-offsets/1`, { length: 50 });
  await page.goto(`${base}/#/c/${s}`);
  const panel = page.locator(".teach");
  await panel.waitFor();
  // G49: F1 is refused and the panel says why.
  await panel.locator(".teach-refused", { hasText: "G49" }).waitFor();
  assert.ok(await panel.locator("tr[data-slot=p1] button").isDisabled());
  const idle = () => poll("idle", async () => (await http("GET", `/api/v1/controllers/${s}`)).body.run_state === "idle");
  for (const [slot, text] of [["p1", "G90 G43.4 H1\nG01 X0 Y0 Z0 F3000"], ["p2", "G01 X10."], ["p3", "G01 X0 Y-5."]]) {
    await http("POST", `/api/v1/controllers/${s}/mdi`, { text });
    await idle();
    const button = panel.locator(`tr[data-slot=${slot}] button`);
    await poll(`${slot} latch enabled`, async () => !(await button.isDisabled()));
    await button.click();
    await poll(`${slot} latched`, async () => (await http("GET", `/api/v1/controllers/${s}/teach`)).body.points.some((p) => p.slot === slot));
  }
  await panel.locator("tr[data-slot=p2] td.num", { hasText: "10.000, 0.000, 0.000" }).waitFor();
  await panel.locator(".teach-actions button:has-text('teach')").click();
  await panel.locator(".teach-block", { hasText: "G68.2 X0. Y0. Z0. I0. J180. K0." }).waitFor();
  // A failed teach says why: two vectors not orthogonal.
  await panel.locator("input[name=teach-mode][value=two_vectors]").check();
  await panel.locator("input[name=teach-x]").fill("1, 0, 0");
  await panel.locator("input[name=teach-z]").fill("1, 0, 1");
  await panel.locator(".teach-actions button:has-text('teach')").click();
  await panel.locator(".teach-failed", { hasText: "orthogonal" }).waitFor();
  await panel.locator("input[name=teach-mode][value=three_points]").check();
  await panel.locator(".teach-actions button:has-text('teach')").click();
  await panel.locator(".teach-block").waitFor();
  await page.screenshot({ path: join(shots, "controller-teach.png") });
  // F2: G49 and the block in MDI; the plane is in force (F1 is refused, G49 now); F8 ends it.
  await panel.locator(".teach-actions button:has-text('F2')").click();
  await poll("G68.2 in force", async () => (await http("GET", `/api/v1/controllers/${s}/modal`)).body.groups["16"] === "G68.2");
  await panel.locator(".teach-refused", { hasText: "G49" }).waitFor();
  await idle();
  await panel.locator(".teach-actions button:has-text('F8')").click();
  await poll("G69 again", async () => (await http("GET", `/api/v1/controllers/${s}/modal`)).body.groups["16"] === "G69");
});

test("a Haas controller is created from the dialect selector: its parameters are Settings, it runs M97, no Teach panel", async () => {
  await page.goto(base + "/");
  await page.fill("form.create input[name=name]", "haas vf2");
  await page.selectOption("form.create select[name=preset]", "mill3");
  await page.selectOption("form.create select[name=dialect]", "haas");
  await page.click("form.create button[type=submit]");
  await page.waitForURL(/#\/c\//);
  const h = decodeURIComponent(page.url().split("#/c/")[1].split("/")[0]);
  await page.locator(".ctl-head h1", { hasText: "haas vf2" }).waitFor();
  await page.locator(".ctl-head .meta", { hasText: "HAAS" }).waitFor();
  assert.equal((await http("GET", `/api/v1/controllers/${h}`)).body.dialect, "haas");
  assert.equal(await page.locator(".teach").count(), 0, "no Teach panel on a Haas controller");
  // M97 calls N100 of the same program; the program ends at its M30.
  const text = "G00 X0 Y0\nM97 P100 L2\nG01 X20. F3000.\nM30\nN100 #100=[#100+1]\nM99\n";
  await http("PUT", `/api/v1/controllers/${h}/programs/1`, text, "text/plain");
  await http("POST", `/api/v1/controllers/${h}/cycle-start`, { program: 1 });
  await poll("the Haas run ends", async () => (await http("GET", `/api/v1/controllers/${h}`)).body.run_state === "idle");
  assert.equal((await http("GET", `/api/v1/controllers/${h}/variables/100`)).body.value, 2);
  await page.goto(`${base}/#/c/${h}/parameters`);
  await page.locator(".parameters input[placeholder^='Setting']").waitFor();
});

test("responsiveness: 200 controllers in the fleet view and a 100,000-point trace (measured)", async () => {
  const have = (await http("GET", "/api/v1/controllers")).body.length;
  for (let i = have; i < 200; i++) await http("POST", "/api/v1/controllers", { name: `bulk ${i}`, preset: ["mill3", "head-bc", "table-ac", "mixed-bc"][i % 4] });
  const started = Date.now();
  await page.goto(base + "/#/");
  await poll("200 rows", async () => (await page.locator(".fleet-table tbody tr").count()) >= 200);
  const fleetMs = Date.now() - started;
  // The longest gap between animation frames over two seconds of live updates.
  const gap = () =>
    page.evaluate(
      () =>
        new Promise((ok) => {
          let last = performance.now(),
            worst = 0;
          const end = last + 2000;
          const step = (t) => {
            worst = Math.max(worst, t - last);
            last = t;
            t < end ? requestAnimationFrame(step) : ok(worst);
          };
          requestAnimationFrame(step);
        }),
    );
  const fleetGap = await gap();
  const c = (await http("GET", "/api/v1/controllers")).body.find((c) => c.name === "cell 1");
  await page.goto(`${base}/#/c/${c.id}`);
  await page.locator(".view3d canvas").waitFor();
  const traceMs = await page.evaluate(() => {
    const view = window.__fivexView;
    const t0 = performance.now();
    for (let i = 0; i < 100000; i++) view.addTrace(Math.cos(i / 500) * 80, Math.sin(i / 500) * 80, (i / 100000) * 50);
    return performance.now() - t0;
  });
  // One full render of the scene with the trace (software WebGL here: SwiftShader).
  const renderMs = await page.evaluate(() => {
    const view = window.__fivexView.view;
    view.render();
    const t0 = performance.now();
    for (let i = 0; i < 10; i++) view.render();
    return (performance.now() - t0) / 10;
  });
  const traceGap = await gap();
  await page.screenshot({ path: join(shots, "trace-100k.png") });
  console.log(`  fleet of 200: rows shown in ${fleetMs} ms, longest frame gap ${fleetGap.toFixed(0)} ms; 100,000 trace points added in ${traceMs.toFixed(0)} ms, a render with them ${renderMs.toFixed(1)} ms, longest frame gap after ${traceGap.toFixed(0)} ms`);
});

test("the workpiece put through the API is drawn on the table, rides with it, is listed, follows another client's change and is cleared from its tab", async () => {
  const made = await http("POST", "/api/v1/controllers", { name: "workpiece", preset: "table-ac" });
  assert.equal(made.status, 201, JSON.stringify(made.body));
  const cid = made.body.id;
  // A block on the table and a smaller one on it (table frame: the table top is Z0).
  const workpiece = { boxes: [{ min: [-60, -40, 0], max: [60, 40, 30] }, { min: [-20, -20, 30], max: [20, 20, 50] }] };
  const put = await http("PUT", `/api/v1/controllers/${cid}/workpiece`, workpiece);
  assert.equal(put.status, 200, JSON.stringify(put.body));
  await page.goto(`${base}/#/c/${cid}/workpiece`);
  await page.locator(".view3d canvas").waitFor();
  await page.locator(".pill.live").waitFor();
  // What the page draws: the boxes under the table frame, and their corners in the world
  // against the table's own mapping of the same table-frame points.
  const drawn = () =>
    page.evaluate(() => {
      const s = window.__fivexView?.view.machineScene;
      if (!s) return null;
      s.rig.root.updateMatrixWorld(true);
      const w = s.workpiece.object;
      const corners = w.children.map((g) => g.localToWorld(g.position.clone().set(1, 1, 1)).toArray());
      return { onTable: w.parent === s.rig.tableFrame, count: w.children.length, corners, axes: s.getAxes(), want: w.children.map((_, i) => s.rig.kinematics.tableToMachine(s.workpiece.boxes[i].max.toArray(), s.getAxes())) };
    });
  const near = (a, b) => a.every((x, i) => Math.abs(x - b[i]) <= 1e-6);
  const first = await poll("the workpiece drawn", async () => ((await drawn())?.count === 2 ? drawn() : null));
  assert.ok(first.onTable, "the boxes are children of the table frame");
  // The table turns: the boxes turn with it (the tool up, out of the way of the picture).
  const mdi = await http("POST", `/api/v1/controllers/${cid}/mdi`, { text: "G90 G00 Z250. A30. C45." });
  assert.equal(mdi.status, 200, JSON.stringify(mdi.body));
  const turned = await poll("the table at A30 C45", async () => {
    const d = await drawn();
    return d && d.axes.A === 30 && d.axes.C === 45 && d.axes.Z === 250 ? d : null;
  });
  turned.corners.forEach((c, i) => assert.ok(near(c, turned.want[i]), `box ${i}: drawn ${c}, table ${turned.want[i]}`));
  assert.ok(!near(turned.corners[0], first.corners[0]), "the corner moved with the table");
  // The tab lists them.
  const rows = await page.locator("[data-testid=workpiece-boxes] tbody tr").count();
  assert.equal(rows, 2);
  await page.click(".ctl-head h1");
  await page.keyboard.press("f");
  await page.waitForTimeout(300);
  await page.locator(".view3d").screenshot({ path: join(shots, "workpiece.png") });
  assert.ok((await colours(".view3d")) > 20, "a drawn scene");
  // Another client puts one box in their place: this page redraws and relists it from the
  // controller's stream, without a reload (the mark set on this document survives).
  await page.evaluate(() => (window.__noReload = true));
  const other = { boxes: [{ min: [-30, -30, 0], max: [30, 30, 80] }] };
  const again = await http("PUT", `/api/v1/controllers/${cid}/workpiece`, other);
  assert.equal(again.status, 200, JSON.stringify(again.body));
  const redrawn = await poll("the other client's box drawn", () =>
    page.evaluate(() => {
      const s = window.__fivexView?.view.machineScene;
      return s && s.workpiece.boxes.length === 1 ? { min: s.workpiece.boxes[0].min.toArray(), max: s.workpiece.boxes[0].max.toArray(), count: s.workpiece.object.children.length } : null;
    }),
  );
  assert.deepEqual(redrawn, { min: [-30, -30, 0], max: [30, 30, 80], count: 1 });
  await poll("the tab relists it", async () => ((await page.locator("[data-testid=workpiece-boxes] tbody tr").count()) === 1 ? true : null));
  const cells = await page.locator("[data-testid=workpiece-boxes] tbody tr td").allTextContents();
  assert.deepEqual(cells.map(Number), [-30, -30, 0, 30, 30, 80]);
  assert.deepEqual(JSON.parse(await page.locator("textarea[aria-label='workpiece JSON']").inputValue()), other, "the editor too");
  assert.equal(await page.evaluate(() => window.__noReload), true, "no reload");
  // Cleared from the tab: nothing on the table, nothing drawn.
  await page.click(".workpiece button:has-text('Clear the table')");
  await poll("the table cleared", async () => ((await drawn())?.count === 0 ? true : null));
  assert.deepEqual((await http("GET", `/api/v1/controllers/${cid}/workpiece`)).body, { boxes: [] });
  await page.locator("[data-testid=workpiece-empty]").waitFor();
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

test("a program save the service refuses shows its reason and keeps the draft; an unsaved edit is not thrown away without asking", async () => {
  const created = await http("POST", "/api/v1/controllers", { name: "edits", preset: "table-ac" });
  const cid = created.body.id;
  const six = "O0006\nG90\nM30\n";
  assert.equal((await http("PUT", `/api/v1/controllers/${cid}/programs/6`, six, "text/plain")).status, 201);
  assert.equal((await http("PUT", `/api/v1/controllers/${cid}/programs/7`, "O0007\nG91\nM30\n", "text/plain")).status, 201);
  await page.goto(`${base}/#/c/${encodeURIComponent(cid)}`);
  await page.click(".prog-list a[data-program='6']");
  await page.locator(".prog-bar strong", { hasText: "O0006" }).waitFor();
  await page.locator(".code .line[data-line='2']", { hasText: "G90" }).waitFor();
  await page.click(".prog-bar button:has-text('edit')");
  // Another O number than the slot: 422 with details {slot, text_number} — the reason shows,
  // with "check & save" and with "save anyway", and the text stays in the editor.
  const nine = "O0009\nG90\nM30\n";
  await page.fill("textarea.nc", nine);
  for (const button of ["button[data-action=save]", "button:has-text('save anyway')"]) {
    await page.click(button);
    await page.locator("p.error", { hasText: "O0009 but would be stored as O0006" }).waitFor();
    assert.equal(await page.locator("textarea.nc").inputValue(), nine);
    await page.click("p.error");
  }
  // Two programs in the text: 422 with details {slot, line, text_number} — the reason, and the
  // second program's line marked.
  const two = "O0006\nG90\nG00 X20. Y10.\nM30\nO0007\nG00 X1.\nM30\n";
  await page.fill("textarea.nc", two);
  await page.click("button:has-text('save anyway')");
  await page.locator("p.error", { hasText: "second program O0007 at line 5" }).waitFor();
  await page.locator("ul.diags li", { hasText: "line 5" }).waitFor();
  assert.equal(await page.locator("textarea.nc").inputValue(), two);
  assert.equal((await http("GET", `/api/v1/controllers/${cid}/programs/6`)).body, six, "nothing stored");
  // Another program clicked with the edit unsaved: asked; "Cancel" keeps the draft.
  const before = dialogsSeen.length;
  dialogAnswers.push(false);
  await page.click(".prog-list a[data-program='7']");
  await poll("the confirm", async () => dialogsSeen.length > before);
  assert.equal(dialogsSeen[before].type, "confirm");
  assert.match(dialogsSeen[before].message, /unsaved changes to O0006/);
  assert.equal(await page.locator("textarea.nc").inputValue(), two, "the draft is kept");
  await page.locator(".prog-bar strong", { hasText: "O0006" }).waitFor();
  // A reload asks too (beforeunload); accepted, the page reloads.
  const asked = dialogsSeen.length;
  await page.reload();
  assert.ok(dialogsSeen.slice(asked).some((d) => d.type === "beforeunload"), JSON.stringify(dialogsSeen.slice(asked)));
  // Without an unsaved edit nothing asks: a program is opened, edited back to what it was, and
  // another one selected.
  await page.click(".prog-list a[data-program='6']");
  await page.locator(".prog-bar strong", { hasText: "O0006" }).waitFor();
  await page.click(".prog-bar button:has-text('edit')");
  await page.fill("textarea.nc", six);
  const quiet = dialogsSeen.length;
  await page.click(".prog-list a[data-program='7']");
  await page.locator(".code .line[data-line='2']", { hasText: "G91" }).waitFor();
  assert.equal(dialogsSeen.length, quiet, "no question without an unsaved edit");
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

test("a refused or unreadable offset puts the stored value back in its cell and says why", async () => {
  const created = await http("POST", "/api/v1/controllers", { name: "offsets", preset: "table-ac" });
  const cid = created.body.id;
  await page.goto(`${base}/#/c/${encodeURIComponent(cid)}/offsets`);
  const cell = page.locator("tr[data-tool='1'] td[data-field=length] input");
  const stored = async () => (await http("GET", `/api/v1/controllers/${cid}/tool-offsets`)).body.find((t) => t.number === 1).length;
  const held = String(await stored());
  await poll("offset 1's length", async () => (await cell.count()) && (await cell.inputValue()) === held);
  await cell.fill("1000");
  await cell.press("Enter");
  await page.locator("p.error", { hasText: "999.999" }).waitFor();
  await poll("the refused value taken back", async () => (await cell.inputValue()) === held);
  assert.equal(String(await stored()), held);
  await page.click("p.error");
  await cell.fill("abc");
  await cell.press("Enter");
  await page.locator("p.error", { hasText: '"abc" is not a number' }).waitFor();
  assert.equal(await cell.inputValue(), held);
  assert.equal(String(await stored()), held);
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

test("under G20 the readout shows the program's positions and F in inch, every length with its unit; after G49 the tool length is 0", async () => {
  const created = await http("POST", "/api/v1/controllers", { name: "inch", preset: "table-ac" });
  const cid = created.body.id;
  const inch = "O0010\nG20 G90 G54\nG00 X1. Y2. Z3.\nG01 X2. F10.\nG04 P2000\nM30\n";
  assert.equal((await http("PUT", `/api/v1/controllers/${cid}/programs/10`, inch, "text/plain")).status, 201);
  // Until a position frame tells it the tool length is unknown: "—", not 0 (a second page
  // whose stream lets no position frame through).
  const blind = await browser.newPage();
  await blind.routeWebSocket(/\/stream/, (ws) => {
    const server = ws.connectToServer();
    server.onMessage((m) => !/"type"\s*:\s*"position"/.test(String(m)) && ws.send(m));
  });
  await blind.goto(`${base}/#/c/${encodeURIComponent(cid)}`);
  await blind.locator(".pos tr[data-axis=X] td.abs").waitFor();
  await blind.locator(".pill.live").waitFor();
  await blind.waitForTimeout(300);
  assert.equal(await blind.locator(".position .tool-length").textContent(), "—", "no tool length before a position frame");
  await blind.close();
  await page.goto(`${base}/#/c/${encodeURIComponent(cid)}`);
  await page.locator(".pos tr[data-axis=X] td.abs").waitFor();
  assert.equal((await http("POST", `/api/v1/controllers/${cid}/cycle-start`, { program: 10 })).status, 200);
  await poll("X 2.0000 in", async () => (await textOf(".pos tr[data-axis=X] td.abs")) === "2.0000");
  const heads = (await page.locator(".pos thead th").allTextContents()).map((t) => t.trim());
  assert.ok(heads.some((h) => /^absolute in/.test(h)), heads.join("|"));
  assert.ok(heads.some((h) => /^relative in/.test(h)), heads.join("|"));
  assert.ok(heads.some((h) => /^machine mm/.test(h)), heads.join("|"));
  assert.ok(heads.some((h) => /^distance to go in/.test(h)), heads.join("|"));
  assert.equal(await textOf(".pos tr[data-axis=Y] td.abs"), "2.0000");
  assert.equal(await textOf(".pos tr[data-axis=Z] td.abs"), "3.0000");
  await poll("modal F 10 in/min", async () => (await textOf(".modal .modal-f")).replace(/\s+/g, " ").trim() === "F 10 in/min");
  assert.match(await textOf(".position .feed"), /mm\/min/);
  assert.match(await textOf(".pos tr[data-axis=A] th"), /°/);
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 20000 });
  // G21 again: mm, 3 decimals.
  const metric = "O0011\nG21 G90 G54\nG00 X50.8\nM30\n";
  assert.equal((await http("PUT", `/api/v1/controllers/${cid}/programs/11`, metric, "text/plain")).status, 201);
  assert.equal((await http("POST", `/api/v1/controllers/${cid}/cycle-start`, { program: 11 })).status, 200);
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 20000 });
  await poll("X 50.800 mm", async () => (await textOf(".pos tr[data-axis=X] td.abs")) === "50.800" && /^absolute mm/.test((await textOf(".pos thead th:nth-child(2)")).trim()));
  // G49 without a motion: the tip is read with no tool length, and the readout says 0.
  assert.equal((await http("PUT", `/api/v1/controllers/${cid}/tool-offsets/1`, { length: 120.5 })).status, 200);
  const g49 = "O0012\nG90 G54 G00 X0 Y0 Z200.\nG43 H1 Z100.\nG49\nM30\n";
  assert.equal((await http("PUT", `/api/v1/controllers/${cid}/programs/12`, g49, "text/plain")).status, 201);
  assert.equal((await http("POST", `/api/v1/controllers/${cid}/cycle-start`, { program: 12 })).status, 200);
  await page.locator("[data-run-state=idle]").waitFor({ timeout: 20000 });
  await poll("tool length 0.000 mm after G49", async () => (await textOf(".position .tool-length")).replace(/\s+/g, " ").trim() === "0.000 mm");
  await page.goto(base + "/");
  assert.equal((await http("DELETE", `/api/v1/controllers/${cid}`)).status, 204);
});

let failed = 0;
// E2E_ONLY=<regular expression>: only the tests whose names match (a part, while working on it).
let ran = 0;
const only = process.env.E2E_ONLY ? new RegExp(process.env.E2E_ONLY) : null;
for (const [name, fn] of tests) {
  if (only && !only.test(name)) continue;
  ran++;
  try {
    await fn();
    console.log(`ok - ${name}`);
  } catch (e) {
    failed++;
    console.log(`FAILED - ${name}\n  ${e.stack ?? e}`);
    await page.screenshot({ path: join(shots, `failed-${tests.findIndex((t) => t[0] === name)}.png`) }).catch(() => {});
  }
}
if (problems.length) {
  failed++;
  console.log(`FAILED - the page reported errors:\n  ${problems.join("\n  ")}`);
}
await browser.close();
stop();
console.log(failed ? `${failed} failed` : `all ${ran} passed`);
process.exit(failed ? 1 : 0);
