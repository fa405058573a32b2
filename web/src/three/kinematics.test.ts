import { describe, expect, it } from "vitest";
import { fixture } from "./fixtures/fixture";
import { Kinematics, sinCosDeg } from "./kinematics";
import { MAIN_CHAIN, chainList, chainView } from "./chain";
import type { FixturePose } from "./fixtures/fixture";
import type { Vec3 } from "./model";

const TOL = 1e-9;

function maxDiff(a: Vec3, b: readonly number[]): number {
  return Math.max(Math.abs(a[0] - b[0]), Math.abs(a[1] - b[1]), Math.abs(a[2] - b[2]));
}

describe("sinCosDeg", () => {
  it("is exact at quarter turns", () => {
    expect(sinCosDeg(90)).toEqual([1, 0]);
    expect(sinCosDeg(-90)).toEqual([-1, 0]);
    expect(sinCosDeg(180)).toEqual([0, -1]);
    expect(sinCosDeg(-270)).toEqual([1, 0]);
    expect(sinCosDeg(720)).toEqual([0, 1]);
  });
  it("agrees with Math.sin/cos elsewhere", () => {
    for (let d = -1000; d <= 1000; d += 7.3) {
      const [s, c] = sinCosDeg(d);
      expect(Math.abs(s - Math.sin((d * Math.PI) / 180))).toBeLessThan(1e-14);
      expect(Math.abs(c - Math.cos((d * Math.PI) / 180))).toBeLessThan(1e-14);
    }
  });
});

/** The page's FK of every pose equals the engine's (tip and tool, both frames) to 1e-9. */
function agrees(source: string, kin: Kinematics, poses: FixturePose[]): void {
  expect(poses.length).toBeGreaterThanOrEqual(10);
  for (const p of poses) {
    const pose = kin.forward(p.axes, p.tool_length);
    const where = `${source} ${JSON.stringify(p.axes)} L${p.tool_length}`;
    expect(maxDiff(pose.tipMachine, p.tip_machine), `${where} tip_machine`).toBeLessThanOrEqual(TOL);
    expect(maxDiff(pose.toolMachine, p.tool_machine), `${where} tool_machine`).toBeLessThanOrEqual(TOL);
    expect(maxDiff(pose.tip, p.tip), `${where} tip`).toBeLessThanOrEqual(TOL);
    expect(maxDiff(pose.tool, p.tool), `${where} tool`).toBeLessThanOrEqual(TOL);
    // The table frame is the inverse of the table motion.
    expect(maxDiff(kin.tableToMachine(pose.tip, p.axes), p.tip_machine)).toBeLessThanOrEqual(TOL);
  }
}

describe("forward kinematics agrees with `fivex kin fk`", () => {
  it("covers every preset kind", () => {
    const kinds = new Set(fixture.machines.map((m) => new Kinematics(m.model).kind));
    for (const k of ["three-axis", "head-head", "table-table", "head-table", "head", "table"]) {
      expect(kinds.has(k as never), k).toBe(true);
    }
  });

  for (const m of fixture.machines) {
    it(m.source, () => agrees(m.source, new Kinematics(m.model), m.poses));
  }

  it("reproduces the hand-worked examples of machine-config.md", () => {
    const hb = fixture.machines.find((m) => m.source === "head-bc")!;
    const p = new Kinematics(hb.model).forward({ X: 10, Y: 20, Z: 30, B: 90, C: 0 }, 100);
    expect(p.tipMachine).toEqual([-240, 20, 180]);
    expect(p.toolMachine).toEqual([1, 0, 0]);
    const ta = fixture.machines.find((m) => m.source === "table-ac")!;
    const q = new Kinematics(ta.model).forward({ X: 0, Y: 0, Z: 50, A: 90, C: 0 }, 0);
    expect(maxDiff(q.tip, [0, -170, -120])).toBe(0);
    expect(maxDiff(q.tool, [0, -1, 0])).toBe(0);
  });
});

describe("each mechanism chain's kinematics agrees with `fivex kin fk --chain`", () => {
  const chained = fixture.machines.filter((m) => m.chains?.length);

  it("covers the library's exchangeable-head machine (set 2) and sub-chains of set 1 and set 2", () => {
    const listed = chained.flatMap((m) => m.chains!.map((c) => `${m.source} ${c.chain.set},${c.chain.sub}`));
    expect(listed).toContain("library/head-exchange-bc-ac.json 2,1");
    expect(listed.some((l) => l.endsWith(" 1,2"))).toBe(true);
    expect(listed.some((l) => l.endsWith(" 2,3"))).toBe(true);
  });

  for (const m of chained) {
    it(`${m.source}: lists the chains as the engine does`, () => {
      expect(chainList(m.model)).toEqual([MAIN_CHAIN, ...m.chains!.map((c) => c.chain)]);
    });
    for (const c of m.chains!) {
      it(`${m.source} chain ${c.chain.set},${c.chain.sub}`, () => {
        const view = chainView(m.model, c.chain);
        expect(view).not.toBeNull();
        agrees(`${m.source} ${c.chain.set},${c.chain.sub}`, new Kinematics(view!), c.poses);
      });
    }
  }

  it("a chain the machine does not describe has no view", () => {
    const m = fixture.machines.find((x) => x.source === "library/head-exchange-bc-ac.json")!;
    expect(chainView(m.model, { set: 3, sub: 1 })).toBeNull();
    expect(chainView(m.model, { set: 2, sub: 2 })).toBeNull();
    expect(chainView(m.model, MAIN_CHAIN)!.rotary.map((r) => r.axis)).toEqual(["C", "B"]);
  });
});
