#!/usr/bin/env node
// Screenshots of the demo page for every preset, for looking at the drawing:
//   npx vite --port 5177 &        (from web/)
//   node src/three/demo/shot.mjs [outdir] [base-url]
// Uses Debian's chromium through playwright-core (CHROMIUM overrides the path).
import { chromium } from "playwright-core";
import { mkdirSync } from "node:fs";

const out = process.argv[2] ?? "/tmp/fivex-3d-shots";
const base = process.argv[3] ?? "http://127.0.0.1:5177/src/three/demo/index.html";
mkdirSync(out, { recursive: true });
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  args: ["--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
});
const page = await browser.newPage({ viewport: { width: 900, height: 640 } });
page.on("console", (m) => m.type() === "error" && console.error("console:", m.text()));
page.on("pageerror", (e) => console.error("pageerror:", e.message));
const shots = (process.env.SHOTS ?? [
  "mill3&X=100&Z=50",
  "head-bc&B=45&C=30",
  "head-bc&B=-90&C=90&view=front",
  "table-ac&A=30&C=45",
  "table-ac&A=90&C=0&view=front",
  "table-bc&B=60&C=20",
  "mixed-bc&B=-45&C=60",
  "machines/head-a4.json&A=30",
  "machines/table-a4.json&A=30",
  "machines/head-nutating.json&B=90&C=20",
  "machines/table-hypothetical.json&C=20",
  "machines/mixed-horizontal.json&A=20&B=30",
].join("|")).split("|");
for (const s of shots) {
  const t0 = Date.now();
  await page.goto(`${base}?machine=${s}`);
  await page.waitForFunction(() => window.demoReady === true, null, { timeout: 20000 });
  await page.waitForTimeout(300);
  const file = `${out}/${s.replace(/[^a-zA-Z0-9=-]+/g, "_")}.png`;
  await page.screenshot({ path: file });
  console.log(file, Date.now() - t0, "ms");
}
if (process.env.PERF) {
  // 100,000+ trace points streamed while the machine moves: JS time per frame.
  await page.goto(`${base}?machine=table-ac`);
  await page.waitForFunction(() => window.demoReady === true, null, { timeout: 20000 });
  const r = await page.evaluate(async (PERF_POINTS) => {
    const h = window.demoHandle;
    window.perfPoints = PERF_POINTS;
    h.clearTrace();
    const js = [];
    const frames = [];
    let last = performance.now();
    for (let f = 0; f < 200; f++) {
      await new Promise((res) => requestAnimationFrame(res));
      const now = performance.now();
      frames.push(now - last);
      last = now;
      const t0 = performance.now();
      for (let i = 0; i < (window.perfPoints ?? 1000); i++) {
        const k = f * 1000 + i;
        h.addTrace(Math.cos(k / 5000) * 150, Math.sin(k / 3000) * 150, (k % 1000) / 20);
      }
      h.view.setAxes({ A: Math.sin(f / 20) * 60, C: f * 2, X: f, Z: 20 });
      js.push(performance.now() - t0);
    }
    const s = (a) => [...a].sort((x, y) => x - y);
    const js2 = s(js), fr = s(frames);
    return { points: h.view.machineScene.trace.length, jsMedianMs: js2[100], jsMaxMs: js2[199], frameMedianMs: fr[100], frameP95Ms: fr[190] };
  }, Number(process.env.PERF_POINTS ?? 1000));
  console.log("perf", JSON.stringify(r));
  await page.screenshot({ path: `${out}/perf-trace.png` });
}
await browser.close();
