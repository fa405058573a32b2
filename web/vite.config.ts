import { defineConfig } from "vitest/config";

// The dashboard is served by `fivex serve` at `/`; `npm run dev` proxies the API to a local
// server on :8080 so the page can be developed with hot reload.
export default defineConfig({
  build: { outDir: "dist", emptyOutDir: true, chunkSizeWarningLimit: 1200 },
  server: {
    proxy: {
      "/api": { target: "http://127.0.0.1:8080", ws: true },
      "/healthz": "http://127.0.0.1:8080",
    },
  },
  test: { include: ["src/**/*.test.ts"] },
});
