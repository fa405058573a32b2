// Which mechanism chain a machine executes in, and that chain as a machine of its own.
//
// A Syntec machine may carry up to four mechanism-chain sets (exchangeable heads) and, on a
// spindle-type set, head attachments Q2–Q4 (`docs/machine-config.md`, "Mechanism chains");
// `G10 L5000 P_ Q_` switches, and the stream's position frames say which is in use (`chain`).
// `chainView` is the engine's `MachineConfig::chain_view`: the machine with that chain's
// `rotary`, `tool_axis`, `nose` and `holder` as its own, so `Kinematics` and `buildMachine`
// read any chain exactly as they read set 1.

import { normalizeModel } from "./model";
import type { MachineModel, MachineModelInput } from "./model";

/** A chain: Syntec's set (1–4) and sub-chain (1: the set as described, 2–4 an attachment). */
export interface Chain {
  set: number;
  sub: number;
}

/** Set 1 as described: the machine's main mechanism (every machine has it). */
export const MAIN_CHAIN: Chain = { set: 1, sub: 1 };

export const sameChain = (a: Chain, b: Chain): boolean => a.set === b.set && a.sub === b.sub;

/** Every chain the machine describes, set 1 first (then its sub-chains, then sets 2–4 each followed by its own), as the engine lists them. */
export function chainList(input: MachineModelInput | MachineModel): Chain[] {
  const m = normalizeModel(input);
  const withSubs = (set: number, subs: { q: number }[]): Chain[] => [{ set, sub: 1 }, ...subs.map((s) => ({ set, sub: s.q }))];
  return [...withSubs(1, m.sub_chains), ...m.chains.flatMap((c) => withSubs(c.set, c.sub_chains))];
}

/**
 * The machine with `chain`'s mechanism as its own and no further chains (set 1 as described: the
 * machine itself); null when the machine does not describe that chain.
 */
export function chainView(input: MachineModelInput | MachineModel, chain: Chain): MachineModel | null {
  const m = normalizeModel(input);
  if (sameChain(chain, MAIN_CHAIN)) return m;
  const set = chain.set === 1 ? m : m.chains.find((c) => c.set === chain.set);
  if (!set) return null;
  const tail = chain.sub === 1 ? set : set.sub_chains.find((s) => s.q === chain.sub);
  if (!tail) return null;
  return {
    ...m,
    rotary: set.rotary,
    tool_axis: tail.tool_axis,
    nose: tail.nose,
    holder: tail.holder,
    sub_chains: [],
    chains: [],
  };
}
