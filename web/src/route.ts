// Hash routes: `#/` the fleet, `#/c/{id}` a controller (`#/c/{id}/{tab}`), `#/runs` fleet runs
// (`#/runs/{id}` one run).
import { useEffect, useState } from "preact/hooks";

export type Route = { page: "fleet" } | { page: "controller"; id: string; tab: string } | { page: "runs"; id?: string };

export function parse(hash: string): Route {
  const parts = hash.replace(/^#\/?/, "").split("/").filter(Boolean);
  if (parts[0] === "c" && parts[1]) return { page: "controller", id: decodeURIComponent(parts[1]), tab: parts[2] ?? "program" };
  if (parts[0] === "runs") return parts[1] ? { page: "runs", id: decodeURIComponent(parts[1]) } : { page: "runs" };
  return { page: "fleet" };
}

export function useRoute(): Route {
  const [route, setRoute] = useState(() => parse(location.hash));
  useEffect(() => {
    const on = () => setRoute(parse(location.hash));
    addEventListener("hashchange", on);
    return () => removeEventListener("hashchange", on);
  }, []);
  return route;
}

export function go(hash: string) {
  location.hash = hash;
}
