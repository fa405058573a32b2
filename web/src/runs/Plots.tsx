// Small SVG plots for the fleet comparison: a horizontal bar per machine and lines over time.
// Plain SVG: a few hundred elements at most, nothing to load.

export function Bars({ rows, unit }: { rows: { label: string; value: number | null; bad?: boolean }[]; unit: string }) {
  const max = Math.max(1e-9, ...rows.map((r) => r.value ?? 0));
  const h = 18;
  const labelW = 190;
  const w = 640;
  return (
    <svg class="plot bars" width={w} height={rows.length * h + 24} role="img" aria-label={`bars in ${unit}`}>
      {rows.map((r, i) => {
        const len = r.value == null ? 0 : ((w - labelW - 90) * r.value) / max;
        return (
          <g key={r.label} transform={`translate(0, ${i * h + 4})`}>
            <text x={labelW - 6} y={12} text-anchor="end" class="label">
              {r.label}
            </text>
            <rect x={labelW} y={2} width={Math.max(len, r.value == null ? 0 : 1)} height={h - 6} class={r.bad ? "bar bad" : "bar"} />
            <text x={labelW + len + 6} y={12} class="value">
              {r.value == null ? (r.bad ? "alarm" : "—") : `${r.value.toFixed(2)} ${unit}`}
            </text>
          </g>
        );
      })}
    </svg>
  );
}

/// Lines of `series` (each y value every `dt` seconds) on one time axis.
export function Lines({ series, dt, unit }: { series: { label: string; ys: number[] }[]; dt: number; unit: string }) {
  const w = 640;
  const h = 220;
  const pad = { l: 60, r: 110, t: 10, b: 24 };
  const n = Math.max(1, ...series.map((s) => s.ys.length));
  const ymax = Math.max(1e-9, ...series.flatMap((s) => s.ys));
  const x = (i: number) => pad.l + ((w - pad.l - pad.r) * i) / Math.max(1, n - 1);
  const y = (v: number) => h - pad.b - ((h - pad.t - pad.b) * v) / ymax;
  const colours = ["#4fa3ff", "#38c172", "#f0b429", "#ef4f4f", "#b57bff", "#4fd1c5", "#f687b3", "#a0aec0"];
  return (
    <svg class="plot lines" width={w} height={h} role="img" aria-label={`speed over time in ${unit}`}>
      <line x1={pad.l} y1={h - pad.b} x2={w - pad.r} y2={h - pad.b} class="axis" />
      <line x1={pad.l} y1={pad.t} x2={pad.l} y2={h - pad.b} class="axis" />
      <text x={pad.l - 6} y={pad.t + 10} text-anchor="end" class="value">
        {ymax.toFixed(0)}
      </text>
      <text x={pad.l - 6} y={h - pad.b} text-anchor="end" class="value">
        0
      </text>
      <text x={w - pad.r} y={h - 6} text-anchor="end" class="value">
        {((n - 1) * dt).toFixed(1)} s
      </text>
      {series.map((s, k) => (
        <g key={s.label}>
          <polyline fill="none" stroke={colours[k % colours.length]} stroke-width={1.2} points={s.ys.map((v, i) => `${x(i).toFixed(1)},${y(v).toFixed(1)}`).join(" ")} />
          <text x={w - pad.r + 8} y={pad.t + 12 + k * 14} style={{ fill: colours[k % colours.length] }} class="legend">
            {s.label}
          </text>
        </g>
      ))}
    </svg>
  );
}
