// The units the readout shows its numbers in. The service answers every length in mm and every
// feed in mm/min (mm/rev under G95, 1/min under G93), whatever the program's unit
// (`docs/conventions.md`, "Units and numbers"); a FANUC shows the absolute, relative and
// distance-to-go positions and the modal F in the input unit, G20 inch or G21 mm, and the
// machine position in the machine's unit (fivex's machines are metric). *Decision*
// (`docs/dashboard.md`, "What it shows"): under G20 the page converts those readouts from the
// API's mm (4 decimals, as IS-B's 0.0001 in) and labels every length and feed with its unit.
import type { Schemas } from "../api/client";

export const MM_PER_INCH = 25.4;

/// The input unit in force: inch under G20 (group 6; the Syntec G70 is held and shown as G20),
/// mm otherwise — also before the modal state is known, since the numbers are then the API's mm.
export function inchInput(modal: Schemas["ModalState"] | null | undefined): boolean {
  return modal?.groups["6"] === "G20";
}

/// A length in the input unit: its number (mm from the API, converted under G20) and digits.
export function inInput(mm: number | null | undefined, inch: boolean): { value: number | null; digits: number; unit: string } {
  if (mm == null || !Number.isFinite(mm)) return { value: null, digits: inch ? 4 : 3, unit: inch ? "in" : "mm" };
  return inch ? { value: mm / MM_PER_INCH, digits: 4, unit: "in" } : { value: mm, digits: 3, unit: "mm" };
}

/// The modal F as the program wrote it, with its unit: in/min or in/rev under G20, mm/min or
/// mm/rev under G21, and the inverse time's 1/min (never converted) under G93.
export function modalFeed(modal: Schemas["ModalState"]): { text: string; unit: string } {
  const mode = modal.groups["5"];
  if (mode === "G93") return { text: trim(modal.f), unit: "1/min" };
  const inch = inchInput(modal);
  const per = mode === "G95" ? "rev" : "min";
  return inch ? { text: trim(modal.f / MM_PER_INCH), unit: `in/${per}` } : { text: trim(modal.f), unit: `mm/${per}` };
}

/// A number without the noise of the conversion (254 / 25.4 = 10.000000000000002 → "10").
function trim(v: number): string {
  return String(Number(v.toFixed(4)));
}
