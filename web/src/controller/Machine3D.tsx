// Placeholder until the 3D module lands: the tool tip in the table frame as numbers.
import type { Frame } from "../api/client";

export function Machine3D({ frame }: { machine: any; frame: Frame | null; path: Float32Array | null; onFrame: (f: (frame: Frame) => void) => () => void }) {
  return <div class="view3d">{frame ? frame.tip_table.join(" ") : ""}</div>;
}
