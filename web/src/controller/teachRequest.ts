// What the Teach panel sends: the request of a guidance mode from the values typed, kept apart
// from the component so that it is tested without a page.
import type { components } from "../api/schema";

export type Mode = components["schemas"]["TeachMode"];
type Request = components["schemas"]["TeachRequest"];

/// The boxes each mode uses (P1 always; P2/P3 for three points).
export const SLOTS: Record<Mode, string[]> = {
  three_points: ["p1", "p2", "p3"],
  tool_direction: ["p1"],
  euler: ["p1"],
  two_vectors: ["p1"],
};

/// The values typed, as text: `i`, `j`, `k` (degrees), `x`, `z` ("1, 0, 0").
export type Typed = Partial<Record<"i" | "j" | "k" | "x" | "z", string>>;

function number(name: string, text: string | undefined): number | undefined {
  if (text == null || text.trim() === "") return undefined;
  const v = Number(text);
  if (!Number.isFinite(v)) throw new Error(`${name} is not a number`);
  return v;
}

function vector(name: string, text: string | undefined): [number, number, number] | undefined {
  if (text == null || text.trim() === "") return undefined;
  const parts = text.split(/[\s,]+/).filter((p) => p !== "");
  if (parts.length !== 3) throw new Error(`${name} needs three components`);
  return parts.map((p) => number(name, p) as number) as [number, number, number];
}

/// The request of a mode from what was typed: only the mode's own values are sent (the service
/// refuses the others); a blank angle is left out (0), a value that is not a number throws.
export function teachRequest(mode: Mode, typed: Typed): Request {
  switch (mode) {
    case "three_points":
      return { mode };
    case "tool_direction":
      return { mode, i: number("I", typed.i) };
    case "euler":
      return { mode, i: number("I", typed.i), j: number("J", typed.j), k: number("K", typed.k) };
    case "two_vectors":
      return { mode, x: vector("Xc", typed.x), z: vector("Zc", typed.z) };
  }
}
