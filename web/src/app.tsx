import { useEffect, useState } from "preact/hooks";
import { useRoute } from "./route";
import { FleetView } from "./fleet/FleetView";
import { ControllerView } from "./controller/ControllerView";
import { RunsView } from "./runs/RunsView";
import { Login } from "./Login";

function Health() {
  const [ok, setOk] = useState<boolean | null>(null);
  useEffect(() => {
    const check = () =>
      fetch("/healthz")
        .then((r) => setOk(r.ok))
        .catch(() => setOk(false));
    check();
    const t = setInterval(check, 5000);
    return () => clearInterval(t);
  }, []);
  return (
    <span class={`health ${ok ? "ok" : ok === false ? "down" : ""}`} title="service health">
      {ok ? "service ok" : ok === false ? "service down" : "…"}
    </span>
  );
}

export function App() {
  const route = useRoute();
  return (
    <div class="app">
      <header class="top">
        <a href="#/" class="brand">
          fivex
        </a>
        <nav>
          <a href="#/" class={route.page === "fleet" ? "active" : ""}>
            Fleet
          </a>
          <a href="#/runs" class={route.page === "runs" ? "active" : ""}>
            Fleet runs
          </a>
          <a href="/swagger-ui/" target="_blank">
            API
          </a>
        </nav>
        <Login />
        <Health />
      </header>
      <main>
        {route.page === "fleet" && <FleetView />}
        {route.page === "controller" && <ControllerView key={route.id} id={route.id} tab={route.tab} />}
        {route.page === "runs" && <RunsView key={route.id ?? ""} id={route.id} />}
      </main>
    </div>
  );
}
