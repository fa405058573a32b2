// Typed access to the fivex HTTP API. `schema.d.ts` is generated from openapi/openapi.json
// (`npm run gen`), so a change of the API that the page does not follow fails `tsc`.
import createClient from "openapi-fetch";
import type { components, paths } from "./schema";
import { authFetch, token, tokenQuery } from "./auth";
import { refusal } from "./refusal";

export type Schemas = components["schemas"];
export type Status = Schemas["ControllerStatus"];
export type Frame = Schemas["PositionFrame"];
export type AlarmInfo = Schemas["AlarmInfo"];
export type FleetEntry = Schemas["FleetEntry"];
export type Machine = Schemas["MachineConfig"];
/// A machine document as `POST /controllers` and fleet runs take it: a model or a parameter list.
export type MachineDocument = Schemas["MachineDocument"];
/// The messages of the three websockets (the document's `ControllerMessage`, `FleetMessage`
/// and a fleet run's `Progress`).
export type ControllerMessage = Schemas["ControllerMessage"];
export type FleetMessage = Schemas["FleetMessage"];
export type Progress = Schemas["Progress"];

export { authFetch, token } from "./auth";

/// Every call goes through `authFetch`: the token as a bearer token, and on 401 the login
/// prompt and the same call again.
export const api = createClient<paths>({ baseUrl: location.origin, fetch: (request) => authFetch(request) });

/// An error the service answered, with its JSON reason.
export class ApiError extends Error {
  constructor(
    message: string,
    public status: number,
    public details?: unknown,
  ) {
    super(message);
  }
}

/// What went wrong, for a person: the message of an `Error` (an `ApiError`: the service's
/// reason), else the thrown value as text.
export function errorText(e: unknown): string {
  return e instanceof Error ? e.message : String(e);
}

/// The data of an openapi-fetch answer, or an `ApiError` with the service's reason.
export async function must<T>(
  call: Promise<{ data?: T; error?: unknown; response: Response }>,
): Promise<T> {
  const { data, error, response } = await call;
  if (!response.ok) {
    const details = typeof error === "object" && error !== null ? (error as { details?: unknown }).details : undefined;
    throw new ApiError(refusal(response.status, response.statusText, error).message, response.status, details);
  }
  return data as T;
}

/// The websocket address of an API path (with the token as a query parameter: browsers cannot
/// set headers on a websocket).
export function wsUrl(path: string, query: Record<string, string | number> = {}): string {
  const url = new URL(path, location.href);
  url.protocol = location.protocol === "https:" ? "wss:" : "ws:";
  for (const [k, v] of Object.entries(query)) url.searchParams.set(k, String(v));
  const t = token();
  // Not `searchParams.set`: that writes a space as `+`, which the service reads as a plus.
  if (t) url.search = url.search ? `${url.search}&${tokenQuery(t)}` : `?${tokenQuery(t)}`;
  return url.toString();
}

/// A websocket refused for its token shows only as a close; a plain request then finds out
/// why, and a 401 brings up the login prompt (`authFetch`). One at a time.
let probing = false;
function probeToken() {
  if (probing) return;
  probing = true;
  authFetch("/api/v1/presets")
    .catch(() => undefined)
    .finally(() => (probing = false));
}

/// A websocket that reconnects (after 1 s, then up to 10 s) until closed by `close()`. `M` is
/// the stream's message type from the document (the service writes nothing else).
export function liveSocket<M>(url: () => string, onMessage: (msg: M) => void, onOpen?: (open: boolean) => void) {
  let ws: WebSocket | null = null;
  let closed = false;
  let delay = 1000;
  const connect = () => {
    ws = new WebSocket(url());
    let opened = false;
    ws.onopen = () => {
      opened = true;
      delay = 1000;
      onOpen?.(true);
    };
    ws.onmessage = (e) => {
      try {
        onMessage(JSON.parse(e.data) as M);
      } catch {
        /* not JSON: ignore */
      }
    };
    ws.onclose = () => {
      onOpen?.(false);
      if (!opened && !closed) probeToken();
      if (!closed) {
        setTimeout(connect, delay);
        delay = Math.min(delay * 2, 10000);
      }
    };
  };
  connect();
  return {
    close() {
      closed = true;
      ws?.close();
    },
  };
}

/// Axis values in the machine's order.
export type Axes = Record<string, number>;

export function fmt(v: number | null | undefined, digits = 3): string {
  return v == null || !Number.isFinite(v) ? "—" : v.toFixed(digits);
}
