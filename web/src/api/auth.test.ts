// The login path of `authFetch`: a 401 brings up the prompt, the request goes again with the
// token given, a refused token is asked for again, one question serves every waiting request,
// and a declined prompt leaves the 401. The transport here answers as `fivex serve --token`
// does (401 unless `Authorization: Bearer TOKEN`, the scheme in any case); the browser test
// (`tests/e2e.mjs`) does the same against the real service.
import { describe, expect, test } from "vitest";
import { authFetch, setAsker, setToken, token, tokenQuery } from "./auth";

const TOKEN = "a+b/c=d";

/// The service's check, and what it was sent.
function service() {
  const seen: { auth: string | null; body: string }[] = [];
  const send = (async (request: Request) => {
    const auth = request.headers.get("authorization");
    seen.push({ auth, body: await request.text() });
    const ok = auth != null && /^bearer /i.test(auth) && auth.slice(7) === TOKEN;
    return ok
      ? new Response(JSON.stringify({ ok: true }), { status: 200, headers: { "content-type": "application/json" } })
      : new Response(JSON.stringify({ error: "a bearer token is required" }), { status: 401, headers: { "www-authenticate": "Bearer" } });
  }) as typeof fetch;
  return { seen, send };
}

/// A prompt that answers `answers` in turn and records whether each question said "refused".
function prompt(answers: (string | null)[]) {
  const asked: boolean[] = [];
  setAsker(async (rejected) => {
    asked.push(rejected);
    return answers.shift() ?? null;
  });
  return asked;
}

describe("authFetch", () => {
  test("401 → prompt → the same request again with the token, a wrong token asked for again", async () => {
    setToken(null);
    const asked = prompt(["wrong", TOKEN]);
    const { seen, send } = service();
    const body = "O1\nG01 X1.\nM30\n";
    const answer = await authFetch("http://fivex.test/api/v1/controllers/c/programs/1", { method: "PUT", body }, send);
    expect(answer.status).toBe(200);
    expect(asked).toEqual([false, true]);
    expect(seen).toEqual([
      { auth: null, body },
      { auth: "Bearer wrong", body },
      { auth: `Bearer ${TOKEN}`, body },
    ]);
    expect(token()).toBe(TOKEN);
    // Kept: the next request carries it at once.
    await authFetch("http://fivex.test/api/v1/controllers", undefined, send);
    expect(seen.at(-1)).toEqual({ auth: `Bearer ${TOKEN}`, body: "" });
    expect(asked).toHaveLength(2);
  });

  test("requests refused together wait for one answer", async () => {
    setToken(null);
    const asked = prompt([TOKEN]);
    const { send } = service();
    const answers = await Promise.all(["a", "b", "c"].map((p) => authFetch(`http://fivex.test/api/v1/${p}`, undefined, send)));
    expect(answers.map((r) => r.status)).toEqual([200, 200, 200]);
    expect(asked).toEqual([false]);
  });

  test("a declined prompt leaves the 401 and is not asked again", async () => {
    setToken(null);
    const asked = prompt([null, TOKEN]);
    const { seen, send } = service();
    const first = await authFetch("http://fivex.test/api/v1/controllers", undefined, send);
    expect(first.status).toBe(401);
    expect((await first.json()).error).toMatch(/token/);
    expect((await authFetch("http://fivex.test/api/v1/controllers", undefined, send)).status).toBe(401);
    expect(asked).toEqual([false]);
    expect(seen).toHaveLength(2);
    expect(token()).toBeNull();
  });
});

test("the websocket query percent-encodes the token, + included", () => {
  expect(tokenQuery(TOKEN)).toBe("token=a%2Bb%2Fc%3Dd");
  expect(tokenQuery("a b")).toBe("token=a%20b");
});
