import { describe, expect, it } from "vitest";
import { programNumber } from "./program";

describe("a program text's own number", () => {
  it("is the first program's O number, after % lines, blanks and comments", () => {
    expect(programNumber("O1000\nG90\nM30")).toBe(1000);
    expect(programNumber("%\n\n(header)\n  o0555 (name)\nM99\n%")).toBe(555);
    expect(programNumber(":0102\nM99")).toBe(102);
  });
  it("is null for a text that starts with a block, or names a number only in a comment", () => {
    expect(programNumber("G90 G00 X0\nO0002\nM99")).toBeNull();
    expect(programNumber("(O1)\nG01 X1.")).toBeNull();
    expect(programNumber("")).toBeNull();
  });
});
