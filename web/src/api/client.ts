// Typed access to the fivex HTTP API. `schema.d.ts` is generated from openapi/openapi.json
// (`npm run gen`), so a change of the API that the page does not follow fails `tsc`.
import createClient, { type Middleware } from "openapi-fetch";
import type { components, paths } from "./schema";

export type Schemas = components["schemas"];
export type Status = Schemas["ControllerStatus"];
export type Frame = Schemas["Frame"];
export type AlarmInfo = Schemas["AlarmInfo"];
export type FleetEntry = Schemas["FleetEntry"];

/// The service's token (`fivex serve --token`), taken once from `?token=` and kept.
export function token(): string | null {
  const given = new URLSearchParams(location.search).get("token");
  if (given) localStorage.setItem("fivex.token", given);
  return given ?? localStorage.getItem("fivex.token");
}

/// The token as a header, for the few calls made with plain `fetch` (NC text is not JSON).
export function authHeaders(): Record<string, string> {
  const t = token();
  return t ? { Authorization: `Bearer ${t}` } : {};
}

const auth: Middleware = {
  onRequest({ request }) {
    const t = token();
    if (t) request.headers.set("Authorization", `Bearer ${t}`);
    return request;
  },
};

export const api = createClient<paths>({ baseUrl: location.origin });
api.use(auth);

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

/// The data of an openapi-fetch answer, or an `ApiError` with the service's reason.
export async function must<T>(
  call: Promise<{ data?: T; error?: unknown; response: Response }>,
): Promise<T> {
  const { data, error, response } = await call;
  if (!response.ok) {
    const body = error as { error?: string; details?: unknown } | undefined;
    throw new ApiError(body?.error ?? `${response.status} ${response.statusText}`, response.status, body?.details);
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
  if (t) url.searchParams.set("token", t);
  return url.toString();
}

/// A websocket that reconnects (after 1 s, then up to 10 s) until closed by `close()`.
export function liveSocket(url: () => string, onMessage: (msg: any) => void, onOpen?: (open: boolean) => void) {
  let ws: WebSocket | null = null;
  let closed = false;
  let delay = 1000;
  const connect = () => {
    ws = new WebSocket(url());
    ws.onopen = () => {
      delay = 1000;
      onOpen?.(true);
    };
    ws.onmessage = (e) => {
      try {
        onMessage(JSON.parse(e.data));
      } catch {
        /* not JSON: ignore */
      }
    };
    ws.onclose = () => {
      onOpen?.(false);
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
