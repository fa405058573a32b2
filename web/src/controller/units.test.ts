import { describe, expect, it } from "vitest";
import { inchInput, inInput, modalFeed } from "./units";

const modal = (groups: Record<string, string>, f: number) => ({ groups, f, s: 0, t: 0, h: 0, d: 0, spindle_tool: 0 });

describe("readout units", () => {
  it("G20 is inch input, G21 and an unknown state mm", () => {
    expect(inchInput(modal({ "6": "G20" }, 0))).toBe(true);
    expect(inchInput(modal({ "6": "G21" }, 0))).toBe(false);
    expect(inchInput(null)).toBe(false);
  });

  it("converts the API's mm to inch under G20, 4 decimals", () => {
    expect(inInput(50.8, true)).toEqual({ value: 2, digits: 4, unit: "in" });
    expect(inInput(50.8, false)).toEqual({ value: 50.8, digits: 3, unit: "mm" });
    expect(inInput(undefined, true).value).toBeNull();
  });

  it("shows the modal F in the program's unit: in/min under G20, 1/min under G93 unconverted", () => {
    expect(modalFeed(modal({ "5": "G94", "6": "G20" }, 254))).toEqual({ text: "10", unit: "in/min" });
    expect(modalFeed(modal({ "5": "G95", "6": "G20" }, 2.54))).toEqual({ text: "0.1", unit: "in/rev" });
    expect(modalFeed(modal({ "5": "G94", "6": "G21" }, 3000))).toEqual({ text: "3000", unit: "mm/min" });
    expect(modalFeed(modal({ "5": "G93", "6": "G20" }, 2))).toEqual({ text: "2", unit: "1/min" });
  });
});
