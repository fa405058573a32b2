// The fleet stream's `fleet_delta` applied to the fleet the page holds: removals first, then
// each changed controller in place of the one with its id, or after the others when it is new.
import type { FleetEntry, Schemas } from "../api/client";

export function applyDelta(fleet: FleetEntry[], delta: Schemas["FleetDelta"]): FleetEntry[] {
  const removed = new Set(delta.removed);
  const changed = new Map(delta.controllers.map((c) => [c.id, c]));
  const next = fleet.filter((c) => !removed.has(c.id)).map((c) => changed.get(c.id) ?? c);
  const present = new Set(next.map((c) => c.id));
  for (const c of delta.controllers) if (!present.has(c.id)) next.push(c);
  return next;
}
