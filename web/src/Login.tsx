// The login prompt: shown when the service answers 401 (`fivex serve --token`), it asks for the
// token, and every refused request is sent again with it (`api/auth.ts`). In the header: "sign
// out" while a token is kept, "sign in" after the operator declined.
import { useEffect, useState } from "preact/hooks";
import { setAsker, setToken, token } from "./api/auth";

type Question = { rejected: boolean; answer: (t: string | null) => void };

export function Login() {
  const [question, setQuestion] = useState<Question | null>(null);
  const [declined, setDeclined] = useState(false);
  const [kept, setKept] = useState(token() != null);

  useEffect(() => {
    setAsker((rejected) => new Promise((answer) => setQuestion({ rejected, answer })));
    return () => setAsker(null);
  }, []);

  const answer = (t: string | null) => {
    question?.answer(t);
    setQuestion(null);
    setDeclined(t == null);
    setKept(t != null);
  };
  const signOut = () => {
    setToken(null);
    location.reload();
  };
  // A fresh page asks again at its first 401.
  const signIn = () => location.reload();

  return (
    <>
      {kept && !question && (
        <button class="tiny" data-action="sign-out" title="forget the service's token in this browser" onClick={signOut}>
          sign out
        </button>
      )}
      {declined && !question && (
        <button class="tiny" data-action="sign-in" title="the service needs a token" onClick={signIn}>
          sign in
        </button>
      )}
      {question && (
        <div class="login-backdrop">
          <form
            class="login"
            onSubmit={(e) => {
              e.preventDefault();
              const t = String(new FormData(e.currentTarget).get("token") ?? "");
              answer(t || null);
            }}
          >
            <h2>Token required</h2>
            <p>
              {question.rejected
                ? "The service refused that token. Enter the token it was started with."
                : "This service was started with --token. Enter the token to continue."}
            </p>
            <input name="token" type="password" autocomplete="current-password" aria-label="token" autoFocus />
            <div class="login-actions">
              <button type="button" onClick={() => answer(null)}>
                cancel
              </button>
              <button type="submit" class="primary">
                sign in
              </button>
            </div>
          </form>
        </div>
      )}
    </>
  );
}
