// The service's token (`fivex serve --token`, docs/dashboard.md "Token"): kept in the browser's
// local storage, sent as `Authorization: Bearer` on every request and as `?token=`
// (percent-encoded) on websockets; when the service answers 401 the page asks the operator for
// it and sends the request again.
//
// Decision: local storage, not session storage. The token is one secret for the whole service,
// not a person's login; a shop-floor screen comes back after a restart, and a controller opened
// in a new tab works, without anyone typing it again. Session storage would not protect it
// better from a script in the page, which could read either. "Sign out" removes it.

const KEY = "fivex.token";

type Store = Pick<Storage, "getItem" | "setItem" | "removeItem">;

/// Local storage, or (where there is none: unit tests) a map.
function defaultStore(): Store {
  if (typeof localStorage !== "undefined") return localStorage;
  const map = new Map<string, string>();
  return {
    getItem: (k) => map.get(k) ?? null,
    setItem: (k, v) => void map.set(k, v),
    removeItem: (k) => void map.delete(k),
  };
}

const store: Store = defaultStore();

export function token(): string | null {
  return store.getItem(KEY);
}

/// Keep `t` (`null`: forget the token).
export function setToken(t: string | null) {
  if (t) store.setItem(KEY, t);
  else store.removeItem(KEY);
}

/// `/?token=T` in the address (a link an operator was given): kept, and taken out of the address
/// bar so it does not stay in the history or a shared screenshot.
export function adoptTokenFromAddress() {
  const url = new URL(location.href);
  const given = url.searchParams.get("token");
  if (given == null) return;
  setToken(given);
  url.searchParams.delete("token");
  history.replaceState(history.state, "", url);
}

/// The query parameter of a websocket address: `encodeURIComponent`, so `+` is `%2B` (the
/// service reads `+` as itself, never as a space, and decodes `%XX`).
export function tokenQuery(t: string): string {
  return `token=${encodeURIComponent(t)}`;
}

/// Who asks the operator for a token; `rejected`: the token sent was refused. Resolves with the
/// token, or `null` when the operator declines.
export type Asker = (rejected: boolean) => Promise<string | null>;

let asker: Asker | null = null;
let asking: Promise<string | null> | null = null;
/// The operator declined: no more questions (the websockets keep trying) until the page is
/// loaded again ("sign in").
let declined = false;

/// Set by the login prompt while it is on the page.
export function setAsker(a: Asker | null) {
  asker = a;
}

/// One question at a time: every request refused meanwhile waits for the same answer.
function ask(rejected: boolean): Promise<string | null> {
  if (!asker || declined) return Promise.resolve(null);
  asking ??= asker(rejected).then((given) => {
    asking = null;
    declined = given == null;
    return given;
  });
  return asking;
}

/// `fetch` with the token; on 401 asks for a token (when a prompt is on the page) and sends the
/// request again with it, until the service takes it or the operator declines (then the 401 is
/// the answer).
export async function authFetch(input: RequestInfo | URL, init?: RequestInit, send: typeof fetch = fetch): Promise<Response> {
  const request = new Request(input, init);
  for (;;) {
    const sent = token();
    const attempt = request.clone();
    if (sent) attempt.headers.set("Authorization", `Bearer ${sent}`);
    const response = await send(attempt);
    if (response.status !== 401) return response;
    // Another request was answered with a new token meanwhile: try that before asking.
    if (token() !== sent) continue;
    const given = await ask(sent != null);
    if (given == null) return response;
    setToken(given);
  }
}
