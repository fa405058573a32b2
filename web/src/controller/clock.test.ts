import { describe, expect, it } from "vitest";
import { clock } from "./clock";

describe("the panel's time counters", () => {
  it("show seconds as h:mm:ss, whole seconds down", () => {
    expect(clock(0)).toBe("0:00:00");
    expect(clock(59.9)).toBe("0:00:59");
    expect(clock(61)).toBe("0:01:01");
    expect(clock(3 * 3600 + 25 * 60 + 7.5)).toBe("3:25:07");
    expect(clock(-4)).toBe("0:00:00");
  });
});
