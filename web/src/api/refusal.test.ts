import { describe, expect, it } from "vitest";
import { refusal } from "./refusal";

describe("refusal", () => {
  it("marks check diagnostics on their lines (details: a list)", () => {
    const r = refusal(422, "Unprocessable Entity", {
      error: "check found 1 problem",
      details: [{ code: "PS0010", message: "IMPROPER G-CODE", detail: "G65 without P", line: 2, col: 1 }],
    });
    expect(r.message).toBe("check found 1 problem");
    expect(r.marks).toEqual([{ line: 2, text: "PS0010 IMPROPER G-CODE: G65 without P" }]);
  });

  it("shows the reason when the O number is not the slot (details: {slot, text_number})", () => {
    const error = "the text is program O0009 but would be stored as O0006: store it under 9, or make its O number 6 (or leave it out)";
    const r = refusal(422, "Unprocessable Entity", { error, details: { slot: 6, text_number: 9 } });
    expect(r.message).toBe(error);
    expect(r.marks).toEqual([]);
  });

  it("shows the reason and marks the line of a second program (details: {slot, line, text_number})", () => {
    const error = "the text holds a second program O0007 at line 5: a stored program is one program; store each under its own number";
    const r = refusal(422, "", { error, details: { slot: 6, line: 5, text_number: 7 } });
    expect(r.message).toBe(error);
    expect(r.marks).toEqual([{ line: 5, text: "a second program O0007 starts here" }]);
    // A second program without a number of its own.
    expect(refusal(422, "", { error, details: { slot: 6, line: 5, text_number: null } }).marks).toEqual([{ line: 5, text: "a second program starts here" }]);
  });

  it("never throws and always gives a reason, whatever the body", () => {
    const bodies: unknown[] = [
      undefined,
      null,
      "",
      "Bad Gateway",
      42,
      [],
      { error: "" },
      { error: 3 },
      { details: "oops" },
      { details: 7 },
      { details: [1, "x", null, { line: "2" }] },
      { details: { a: 1 } },
      { error: "no", details: [{ line: 3 }] },
    ];
    for (const b of bodies) {
      const r = refusal(500, "Internal Server Error", b);
      expect(r.message.length).toBeGreaterThan(0);
      expect(Array.isArray(r.marks)).toBe(true);
    }
    expect(refusal(502, "Bad Gateway", "upstream down").message).toBe("502 Bad Gateway: the service gave no reason (upstream down)");
    expect(refusal(422, "", { details: { a: 1 } }).message).toBe('422: the service gave no reason ({"a":1})');
    expect(refusal(422, "", { error: "no", details: [{ line: 3 }] }).marks).toEqual([{ line: 3, text: "refused" }]);
  });
});
