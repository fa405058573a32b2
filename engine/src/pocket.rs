//! The geometry of a general pocket (Haas G150, `interp::haas_cycles`): a closed outline of lines
//! and arcs in the XY plane, the region the tool centre may reach (the outline offset inward by
//! the tool radius plus the finish allowance), the roughing strokes clipped to that region and
//! the passes around it. Pure plane geometry, no machine state.
//!
//! The order of the moves is fivex's decision where the manual describes the cycle only in words
//! (`docs/dialects.md`, "Haas cycles", G150): at each depth the tool goes from the start hole
//! straight to the outline pass's start, runs the outline pass once around, then the roughing
//! strokes in zigzag from the side nearest that start (the stroke's end nearer along the pass,
//! on a tie the one the outline's direction reaches), each linked to the next along the outline
//! pass already cut (the shorter way round; a tie: the outline's direction), then back along it
//! to the pass's start and straight to the hole. Where fivex cannot give an order it can justify (a stroke line crossing the
//! region in several pieces, an offset region that splits or vanishes, a self-intersecting
//! outline) the pocket is refused ([`Refusal`]).

use std::f64::consts::{PI, TAU};

/// A point of the plane (X, Y).
pub type P = [f64; 2];

/// The most roughing strokes of one depth (a 2 m pocket at a 0.1 mm step).
const MAX_STROKES: f64 = 20_000.0;

/// Lengths below this are zero (mm): a closing gap, a vanished segment, a point on a line.
pub const EPS: f64 = 1e-7;

/// One element of an outline: a line, or an arc about `centre` sweeping `sweep` radians
/// (positive counter-clockwise, at most a full turn).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seg {
    pub start: P,
    pub end: P,
    pub arc: Option<(P, f64)>,
}

/// A move of the tool centre from where the last one ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Move {
    Line {
        to: P,
    },
    /// About `centre`, `sweep` radians (positive counter-clockwise).
    Arc {
        to: P,
        centre: P,
        sweep: f64,
    },
}

impl Move {
    pub fn to(&self) -> P {
        match *self {
            Move::Line { to } | Move::Arc { to, .. } => to,
        }
    }
}

/// Why a pocket is not cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// The program breaks the cycle's rules (the manual's, or geometry no pocket can have): the
    /// dialect's cycle-argument alarm.
    Argument(&'static str),
    /// A pocket the manual allows whose order of moves fivex does not build: refused as not built.
    NotBuilt(&'static str),
}

/// What one G150 block cuts, in the XY plane; every list starts and ends at the start hole.
#[derive(Debug, Clone, PartialEq)]
pub struct Pocket {
    /// The moves of every depth pass: entry, outline pass at tool radius + K, roughing, return.
    pub level: Vec<Move>,
    /// The outline pass at the tool radius alone, at the final depth (empty without K).
    pub finish: Vec<Move>,
    /// The region's outline pass (tool radius + K from the wall), from its start, for checks.
    pub contour: Vec<Seg>,
}

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1]]
}
fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1]]
}
fn mul(a: P, k: f64) -> P {
    [a[0] * k, a[1] * k]
}
fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: P, b: P) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn norm(a: P) -> f64 {
    a[0].hypot(a[1])
}
pub fn dist(a: P, b: P) -> f64 {
    norm(sub(a, b))
}
fn unit(a: P) -> P {
    mul(a, 1.0 / norm(a))
}
fn left(a: P) -> P {
    [-a[1], a[0]]
}
fn angle(a: P) -> f64 {
    a[1].atan2(a[0])
}
fn polar(c: P, r: f64, t: f64) -> P {
    [c[0] + r * t.cos(), c[1] + r * t.sin()]
}
/// The angle from `from` to `to` turning the way `sign` says (+1 counter-clockwise), in [0, 2π).
fn turn(from: f64, to: f64, sign: f64) -> f64 {
    ((to - from) * sign).rem_euclid(TAU)
}

impl Seg {
    pub fn line(start: P, end: P) -> Seg {
        Seg { start, end, arc: None }
    }

    fn radius(&self) -> f64 {
        self.arc.map_or(0.0, |(c, _)| dist(self.start, c))
    }

    /// The point at parameter `t` (0 start, 1 end).
    pub fn at(&self, t: f64) -> P {
        // The ends exactly: a crossing at a joint must count on one side of it only.
        if t <= 0.0 {
            return self.start;
        }
        if t >= 1.0 {
            return self.end;
        }
        match self.arc {
            None => add(self.start, mul(sub(self.end, self.start), t)),
            Some((c, s)) => polar(c, self.radius(), angle(sub(self.start, c)) + s * t),
        }
    }

    /// The unit direction of travel at parameter `t`.
    fn tangent(&self, t: f64) -> P {
        match self.arc {
            None => unit(sub(self.end, self.start)),
            Some((c, s)) => {
                let radial = unit(sub(self.at(t), c));
                mul(left(radial), s.signum())
            }
        }
    }

    pub fn length(&self) -> f64 {
        match self.arc {
            None => dist(self.start, self.end),
            Some((_, s)) => self.radius() * s.abs(),
        }
    }

    /// The parameter of a point on the segment (assumed on it).
    fn param(&self, p: P) -> f64 {
        match self.arc {
            None => {
                let d = sub(self.end, self.start);
                (dot(sub(p, self.start), d) / dot(d, d)).clamp(0.0, 1.0)
            }
            Some((c, s)) => {
                let a0 = angle(sub(self.start, c));
                let da = turn(a0, angle(sub(p, c)), s.signum());
                // Within EPS of the start after a full turn is the start.
                let da = if da > s.abs() + 1e-12 && TAU - da < 1e-9 { 0.0 } else { da };
                (da / s.abs()).clamp(0.0, 1.0)
            }
        }
    }

    /// The move along this segment from parameter `a` to `b` (either way).
    fn piece(&self, a: f64, b: f64) -> Move {
        let to = if b >= 1.0 {
            self.end
        } else if b <= 0.0 {
            self.start
        } else {
            self.at(b)
        };
        match self.arc {
            None => Move::Line { to },
            Some((c, s)) => Move::Arc { to, centre: c, sweep: s * (b - a) },
        }
    }

    /// Signed area contribution (shoelace, with the circular segment of an arc).
    fn area(&self) -> f64 {
        let chord = cross(self.start, self.end) / 2.0;
        match self.arc {
            None => chord,
            Some((_, s)) => chord + self.radius().powi(2) * (s - s.sin()) / 2.0,
        }
    }

    /// The lowest and highest value of coordinate `k` along the segment.
    fn range(&self, k: usize) -> (f64, f64) {
        let (mut lo, mut hi) = (self.start[k].min(self.end[k]), self.start[k].max(self.end[k]));
        if let Some((c, s)) = self.arc {
            let r = self.radius();
            let a0 = angle(sub(self.start, c));
            // The extremes of coordinate k are at angle 0/π (X) or π/2, 3π/2 (Y).
            for e in [0.0, PI] {
                let e = e + if k == 1 { PI / 2.0 } else { 0.0 };
                if turn(a0, e, s.signum()) <= s.abs() {
                    let p = polar(c, r, e);
                    lo = lo.min(p[k]);
                    hi = hi.max(p[k]);
                }
            }
        }
        (lo, hi)
    }

    /// The parameters in (0, 1) where coordinate Y is extreme (an arc's top and bottom).
    fn y_turns(&self) -> Vec<f64> {
        let Some((c, s)) = self.arc else { return Vec::new() };
        let a0 = angle(sub(self.start, c));
        let mut ts: Vec<f64> = [PI / 2.0, 3.0 * PI / 2.0]
            .iter()
            .flat_map(|&e| {
                let first = turn(a0, e, s.signum());
                [first, first + TAU]
            })
            .filter(|&d| d > 1e-12 && d < s.abs() - 1e-12)
            .map(|d| d / s.abs())
            .collect();
        ts.sort_by(f64::total_cmp);
        ts
    }

    fn swapped(&self) -> Seg {
        let sw = |p: P| [p[1], p[0]];
        Seg { start: sw(self.start), end: sw(self.end), arc: self.arc.map(|(c, s)| (sw(c), -s)) }
    }
}

fn swap_move(m: Move) -> Move {
    let sw = |p: P| [p[1], p[0]];
    match m {
        Move::Line { to } => Move::Line { to: sw(to) },
        Move::Arc { to, centre, sweep } => Move::Arc { to: sw(to), centre: sw(centre), sweep: -sweep },
    }
}

/// The signed area of a closed outline (positive: counter-clockwise).
pub fn area(outline: &[Seg]) -> f64 {
    outline.iter().map(Seg::area).sum()
}

/// A line (point, direction) or a circle (centre, radius), the carrier of a segment.
#[derive(Clone, Copy)]
enum Carrier {
    Line(P, P),
    Circle(P, f64),
}

fn carrier(s: &Seg) -> Carrier {
    match s.arc {
        None => Carrier::Line(s.start, unit(sub(s.end, s.start))),
        Some((c, _)) => Carrier::Circle(c, s.radius()),
    }
}

/// The points where two carriers meet (none for parallel lines or circles apart).
fn meet(a: Carrier, b: Carrier) -> Vec<P> {
    match (a, b) {
        (Carrier::Line(p, d), Carrier::Line(q, e)) => {
            let den = cross(d, e);
            if den.abs() < 1e-12 {
                return Vec::new();
            }
            let t = cross(sub(q, p), e) / den;
            vec![add(p, mul(d, t))]
        }
        (Carrier::Line(p, d), Carrier::Circle(c, r)) | (Carrier::Circle(c, r), Carrier::Line(p, d)) => {
            // |p + t d − c|² = r²
            let f = sub(p, c);
            let bq = dot(f, d);
            let disc = bq * bq - (dot(f, f) - r * r);
            if disc < -1e-12 {
                return Vec::new();
            }
            let h = disc.max(0.0).sqrt();
            vec![add(p, mul(d, -bq - h)), add(p, mul(d, -bq + h))]
        }
        (Carrier::Circle(c1, r1), Carrier::Circle(c2, r2)) => {
            let dd = dist(c1, c2);
            if dd < 1e-12 || dd > r1 + r2 + 1e-12 || dd < (r1 - r2).abs() - 1e-12 {
                return Vec::new();
            }
            let a = (r1 * r1 - r2 * r2 + dd * dd) / (2.0 * dd);
            let h = (r1 * r1 - a * a).max(0.0).sqrt();
            let u = unit(sub(c2, c1));
            let m = add(c1, mul(u, a));
            vec![add(m, mul(left(u), h)), sub(m, mul(left(u), h))]
        }
    }
}

/// Whether a point of a segment's carrier lies on the segment (within EPS).
fn on_seg(s: &Seg, p: P) -> bool {
    match s.arc {
        None => {
            let d = sub(s.end, s.start);
            let t = dot(sub(p, s.start), d) / dot(d, d);
            let l = norm(d);
            t * l >= -EPS && t * l <= l + EPS && cross(d, sub(p, s.start)).abs() / l < EPS
        }
        Some((c, sw)) => {
            let r = s.radius();
            if (dist(p, c) - r).abs() > EPS {
                return false;
            }
            let da = turn(angle(sub(s.start, c)), angle(sub(p, c)), sw.signum());
            da * r <= sw.abs() * r + EPS || (TAU - da) * r < EPS
        }
    }
}

/// The points two segments share (collinear or concentric overlaps count as one, `true`).
fn crossings(a: &Seg, b: &Seg) -> (Vec<P>, bool) {
    let (ca, cb) = (carrier(a), carrier(b));
    let overlap = match (ca, cb) {
        (Carrier::Line(p, d), Carrier::Line(q, e)) => {
            cross(d, e).abs() < 1e-12
                && cross(d, sub(q, p)).abs() < EPS
                && (on_seg(a, b.start) || on_seg(a, b.end) || on_seg(b, a.start) || on_seg(b, a.end))
        }
        (Carrier::Circle(c1, r1), Carrier::Circle(c2, r2)) => {
            dist(c1, c2) < EPS
                && (r1 - r2).abs() < EPS
                && (on_seg(a, b.start) || on_seg(a, b.end) || on_seg(b, a.start) || on_seg(b, a.end))
        }
        _ => false,
    };
    let pts = meet(ca, cb).into_iter().filter(|&p| on_seg(a, p) && on_seg(b, p)).collect();
    (pts, overlap)
}

/// Whether a closed outline crosses or touches itself anywhere but where consecutive segments
/// join.
fn self_intersects(c: &[Seg]) -> bool {
    let n = c.len();
    for i in 0..n {
        for j in i + 1..n {
            let (pts, overlap) = crossings(&c[i], &c[j]);
            let next = j == i + 1;
            let wrap = i == 0 && j == n - 1;
            // Consecutive segments share their joint; a two-segment outline shares both ends.
            let shared: Vec<P> = match (next, wrap) {
                (true, true) => vec![c[i].end, c[i].start],
                (true, false) => vec![c[i].end],
                (false, true) => vec![c[i].start],
                _ => vec![],
            };
            if overlap && (next || wrap) {
                // Adjacent segments on one line (or circle) go straight on; folding back over
                // each other they cross.
                let on_after_i = next && dot(c[i].tangent(1.0), c[j].tangent(0.0)) > 0.0;
                let on_after_j = wrap && dot(c[j].tangent(1.0), c[i].tangent(0.0)) > 0.0;
                if !(on_after_i || on_after_j) {
                    return true;
                }
                continue;
            }
            if overlap || pts.iter().any(|p| shared.iter().all(|q| dist(*p, *q) > 1e-6)) {
                return true;
            }
        }
    }
    false
}

/// The outline offset inward by `d` (the tool centre's path at `d` from the wall), starting at
/// the offset of the outline's start (at a concave start corner, the middle of the arc about it). Convex corners are the meeting points of the offset
/// elements, concave ones arcs of radius `d` about the corner; a convex arc smaller than `d`
/// gives way to the corner of its neighbours. Refused where the offset loses a segment's
/// direction, turns over, or crosses itself (the region vanishes or splits).
pub fn offset(outline: &[Seg], d: f64) -> Result<Vec<Seg>, Refusal> {
    let n = outline.len();
    let sigma = area(outline).signum();
    let vanished = Refusal::Argument("the tool does not fit the outline (the offset region vanishes)");
    // The raw offsets; a convex arc whose offset radius is not positive is dropped.
    let mut raw: Vec<Option<Seg>> = Vec::with_capacity(n);
    for s in outline {
        let normal = |t: f64| mul(left(s.tangent(t)), sigma);
        match s.arc {
            None => raw.push(Some(Seg::line(add(s.start, mul(normal(0.0), d)), add(s.end, mul(normal(1.0), d))))),
            Some((c, sw)) => {
                let r = s.radius() - sigma * sw.signum() * d;
                if r <= EPS {
                    if sigma * sw.signum() > 0.0 {
                        raw.push(None);
                        continue;
                    }
                    return Err(vanished);
                }
                let a0 = angle(sub(s.start, c));
                raw.push(Some(Seg { start: polar(c, r, a0), end: polar(c, r, a0 + sw), arc: Some((c, sw)) }));
            }
        }
    }
    let kept: Vec<usize> = (0..n).filter(|&i| raw[i].is_some()).collect();
    if kept.is_empty() {
        return Err(vanished);
    }
    let mut segs: Vec<Seg> = kept.iter().map(|&i| raw[i].expect("kept")).collect();
    let m = kept.len();
    // Joins after each kept segment: a trimmed corner or an arc about the vertex.
    let mut joins: Vec<Option<Seg>> = vec![None; m];
    let mut starts: Vec<P> = segs.iter().map(|s| s.start).collect();
    let mut ends: Vec<P> = segs.iter().map(|s| s.end).collect();
    for k in 0..m {
        let (i, j) = (kept[k], kept[(k + 1) % m]);
        let adjacent = (i + 1) % n == j;
        let (t1, t2) = (outline[i].tangent(1.0), outline[j].tangent(0.0));
        let turning = cross(t1, t2);
        let (a, b) = (segs[k], segs[(k + 1) % m]);
        if adjacent && turning.abs() < 1e-6 {
            if dot(t1, t2) < 0.0 {
                return Err(Refusal::Argument("the outline turns back on itself"));
            }
            // Smooth (an arc by R meets its tangent line within the rounding of its centre):
            // the offsets meet, to that rounding; both end at the middle.
            let mid = mul(add(a.end, b.start), 0.5);
            ends[k] = mid;
            starts[(k + 1) % m] = mid;
            continue;
        }
        if adjacent && sigma * turning < 0.0 {
            // Concave corner: the tool rolls about it.
            let v = outline[i].end;
            let sweep = -sigma * turn(angle(sub(a.end, v)), angle(sub(b.start, v)), -sigma);
            joins[k] = Some(Seg { start: a.end, end: b.start, arc: Some((v, sweep)) });
            continue;
        }
        // Convex corner: the offsets meet where their carriers do, nearest the corner.
        let near = mul(add(a.end, b.start), 0.5);
        let p = meet(carrier(&a), carrier(&b))
            .into_iter()
            .min_by(|p, q| dist(*p, near).total_cmp(&dist(*q, near)))
            .ok_or(vanished)?;
        ends[k] = p;
        starts[(k + 1) % m] = p;
        if m == 1 {
            return Err(vanished);
        }
    }
    let mut out = Vec::new();
    for k in 0..m {
        let orig = segs[k];
        let s = match orig.arc {
            None => {
                let t = Seg::line(starts[k], ends[k]);
                if dist(t.start, t.end) < EPS {
                    None
                } else if dot(sub(t.end, t.start), sub(orig.end, orig.start)) <= 0.0 {
                    return Err(vanished);
                } else {
                    Some(t)
                }
            }
            Some((c, sw)) => {
                let full = (sw.abs() - TAU).abs() < 1e-12 && dist(starts[k], ends[k]) < EPS;
                let new = if full {
                    sw
                } else {
                    sw.signum() * turn(angle(sub(starts[k], c)), angle(sub(ends[k], c)), sw.signum())
                };
                if new.abs() * orig.radius() < EPS {
                    None
                } else if new.abs() > sw.abs() + 1e-9 {
                    return Err(vanished);
                } else {
                    Some(Seg { start: starts[k], end: ends[k], arc: Some((c, new)) })
                }
            }
        };
        out.extend(s);
        out.extend(joins[k]);
    }
    // A concave corner at the outline's start (the join after the last element, the tool
    // rolling about the start point): the pass starts where the tool stands at that point, at
    // `d` from it on the corner's bisector (the middle of the arc), not at one end of the arc,
    // an edge's offset beside the corner, whose straight way from the start hole may cut into
    // the corner (the audit's F5: a valid pocket refused as if its start hole were outside).
    if kept[0] == 0 && kept[m - 1] == n - 1 && joins[m - 1].is_some() {
        let arc = out.pop().expect("the join is the last element");
        let (v, sweep) = arc.arc.expect("a join is an arc");
        let mid = polar(v, d, angle(sub(arc.start, v)) + sweep / 2.0);
        out.insert(0, Seg { start: mid, end: arc.end, arc: Some((v, sweep / 2.0)) });
        out.push(Seg { start: arc.start, end: mid, arc: Some((v, sweep / 2.0)) });
    }
    segs = out;
    if segs.is_empty() || area(&segs) * sigma <= EPS * EPS {
        return Err(vanished);
    }
    if self_intersects(&segs) {
        return Err(Refusal::NotBuilt("the offset region splits (a neck narrower than the tool)"));
    }
    Ok(segs)
}

/// A place on a closed contour: segment index and parameter.
#[derive(Debug, Clone, Copy)]
struct Spot {
    seg: usize,
    t: f64,
    p: P,
}

/// The moves along the contour from `a` to `b`, forward (`true`) or backward.
fn walk(c: &[Seg], a: Spot, b: Spot, forward: bool) -> Vec<Move> {
    let n = c.len();
    let mut moves = Vec::new();
    let mut push = |m: Move, from: P| {
        if dist(m.to(), from) > EPS || matches!(m, Move::Arc { sweep, .. } if sweep.abs() > 1e-9) {
            moves.push(m);
        }
    };
    if forward {
        if a.seg == b.seg && b.t >= a.t {
            push(c[a.seg].piece(a.t, b.t), a.p);
            return moves;
        }
        push(c[a.seg].piece(a.t, 1.0), a.p);
        let mut i = (a.seg + 1) % n;
        while i != b.seg {
            push(c[i].piece(0.0, 1.0), c[i].start);
            i = (i + 1) % n;
        }
        push(c[b.seg].piece(0.0, b.t), c[b.seg].start);
    } else {
        if a.seg == b.seg && b.t <= a.t {
            push(c[a.seg].piece(a.t, b.t), a.p);
            return moves;
        }
        push(c[a.seg].piece(a.t, 0.0), a.p);
        let mut i = (a.seg + n - 1) % n;
        while i != b.seg {
            push(c[i].piece(1.0, 0.0), c[i].end);
            i = (i + n - 1) % n;
        }
        push(c[b.seg].piece(1.0, b.t), c[b.seg].end);
    }
    moves
}

fn path_length(from: P, moves: &[Move]) -> f64 {
    let mut at = from;
    let mut len = 0.0;
    for m in moves {
        len += match *m {
            Move::Line { to } => dist(at, to),
            Move::Arc { centre, sweep, .. } => dist(at, centre) * sweep.abs(),
        };
        at = m.to();
    }
    len
}

/// Lengths that differ by less than this are a tie (mm).
const TIE: f64 = 1e-6;

/// The shorter way along the contour from `a` to `b` (a tie: forward, the way the outline
/// runs), its length, and whether it runs forward.
fn link(c: &[Seg], a: Spot, b: Spot) -> (Vec<Move>, f64, bool) {
    let f = walk(c, a, b, true);
    let r = walk(c, a, b, false);
    let (lf, lr) = (path_length(a.p, &f), path_length(a.p, &r));
    if lf <= lr + TIE {
        (f, lf, true)
    } else {
        (r, lr, false)
    }
}

/// Where the horizontal line `y` crosses the contour, sorted by X: each crossing counted once
/// (a half-open rule on Y, arcs split at their top and bottom).
fn crossings_at(c: &[Seg], y: f64) -> Vec<Spot> {
    let mut out = Vec::new();
    for (i, s) in c.iter().enumerate() {
        let mut ts = vec![0.0];
        ts.extend(s.y_turns());
        ts.push(1.0);
        for w in ts.windows(2) {
            let (pa, pb) = (s.at(w[0]), s.at(w[1]));
            if (pa[1] < y) == (pb[1] < y) {
                continue;
            }
            let (t, p) = match s.arc {
                None => {
                    let t = (y - s.start[1]) / (s.end[1] - s.start[1]);
                    (t, [s.start[0] + t * (s.end[0] - s.start[0]), y])
                }
                Some((cc, _)) => {
                    let r = s.radius();
                    let h = (r * r - (y - cc[1]).powi(2)).max(0.0).sqrt();
                    // The piece lies on one side of the centre (split at top and bottom).
                    let mid = s.at((w[0] + w[1]) / 2.0);
                    let x = cc[0] + if mid[0] >= cc[0] { h } else { -h };
                    let p = [x, y];
                    (s.param(p).clamp(w[0], w[1]), p)
                }
            };
            out.push(Spot { seg: i, t, p });
        }
    }
    out.sort_by(|a, b| a.p[0].total_cmp(&b.p[0]));
    out
}

/// Whether `p` is inside the closed contour (crossings to its left odd).
fn inside(c: &[Seg], p: P) -> bool {
    crossings_at(c, p[1]).iter().filter(|s| s.p[0] < p[0]).count() % 2 == 1
}

/// The tool's way from the start hole to the contour's start: straight, and inside the region
/// all the way (else the cycle's start point is not inside the pocket).
fn entry(c: &[Seg], hole: P) -> Result<(), Refusal> {
    let bad =
        Refusal::Argument("the start point X/Y is not inside the pocket, clear of the wall by the tool radius + K");
    let start = c[0].start;
    if dist(hole, start) < EPS {
        return Ok(());
    }
    let way = Seg::line(hole, start);
    for s in c {
        let (pts, overlap) = crossings(&way, s);
        if overlap || pts.iter().any(|p| dist(*p, start) > 1e-6) {
            return Err(bad);
        }
    }
    if !inside(c, mul(add(hole, start), 0.5)) {
        return Err(bad);
    }
    Ok(())
}

fn loop_moves(c: &[Seg]) -> Vec<Move> {
    c.iter().map(|s| s.piece(0.0, 1.0)).collect()
}

/// Plan a pocket. `outline`: the closed outline (from the subprogram, its first element starting
/// where the subprogram's entry move ends); `hole`: the start hole (the block's X/Y); `tool`: the
/// tool radius; `k`: the finish allowance; `step`: the roughing increment (I or J);
/// `strokes_along_x`: J given (the strokes run along X, stepping in Y), else I (along Y).
pub fn plan(outline: &[Seg], hole: P, tool: f64, k: f64, step: f64, strokes_along_x: bool) -> Result<Pocket, Refusal> {
    if step.is_nan() || step <= EPS || tool < 0.0 || k < 0.0 {
        return Err(Refusal::Argument("I/J positive, K not negative, a tool radius not negative"));
    }
    if outline.is_empty() || area(outline).abs() < EPS * EPS {
        return Err(Refusal::Argument("the outline encloses no area"));
    }
    for (i, s) in outline.iter().enumerate() {
        if dist(s.end, outline[(i + 1) % outline.len()].start) > EPS {
            return Err(Refusal::Argument("the outline is not closed"));
        }
    }
    if self_intersects(outline) {
        return Err(Refusal::Argument("the outline crosses itself"));
    }
    // Everything below runs with the strokes along X; I (strokes along Y) swaps the axes.
    let swap = !strokes_along_x;
    let outline: Vec<Seg> = if swap { outline.iter().map(Seg::swapped).collect() } else { outline.to_vec() };
    let hole = if swap { [hole[1], hole[0]] } else { hole };
    let c = offset(&outline, tool + k)?;
    entry(&c, hole)?;
    let mut level = vec![Move::Line { to: c[0].start }];
    level.extend(loop_moves(&c));
    let s0 = Spot { seg: 0, t: 0.0, p: c[0].start };
    // The stroke lines: evenly between the region's lowest and highest Y, at most `step` apart
    // (the extremes are on the outline pass).
    let (lo, hi) = c.iter().map(|s| s.range(1)).fold((f64::MAX, f64::MIN), |(l, h), (a, b)| (l.min(a), h.max(b)));
    let count = ((hi - lo) / step - 1e-9).ceil().max(1.0);
    if count > MAX_STROKES {
        return Err(Refusal::Argument("more than 20000 roughing strokes"));
    }
    let count = count as usize;
    let mut lines: Vec<f64> = (1..count).map(|i| lo + (hi - lo) * i as f64 / count as f64).collect();
    // From the side nearest the outline pass's start.
    if (hi - s0.p[1]) < (s0.p[1] - lo) {
        lines.reverse();
    }
    let mut at = s0;
    let mut left_to_right: Option<bool> = None;
    for y in lines {
        let xs = crossings_at(&c, y);
        if xs.len() != 2 {
            return Err(Refusal::NotBuilt("a roughing stroke crosses the region in several pieces"));
        }
        let (a, b) = (xs[0], xs[1]);
        // The first stroke starts at its end nearer the pass's start; then they alternate.
        // (A tie: the end the outline's own direction reaches.)
        let ltr = match left_to_right {
            None => {
                let ((_, la, fa), (_, lb, fb)) = (link(&c, at, a), link(&c, at, b));
                la < lb - TIE || (la <= lb + TIE && (fa || !fb))
            }
            Some(prev) => !prev,
        };
        left_to_right = Some(ltr);
        let (from, to) = if ltr { (a, b) } else { (b, a) };
        level.extend(link(&c, at, from).0);
        level.push(Move::Line { to: to.p });
        at = to;
    }
    level.extend(link(&c, at, s0).0);
    level.push(Move::Line { to: hole });
    let finish = if k > 0.0 {
        let f = offset(&outline, tool)?;
        entry(&f, hole)?;
        let mut moves = vec![Move::Line { to: f[0].start }];
        moves.extend(loop_moves(&f));
        moves.push(Move::Line { to: hole });
        moves
    } else {
        Vec::new()
    };
    if swap {
        Ok(Pocket {
            level: level.into_iter().map(swap_move).collect(),
            finish: finish.into_iter().map(swap_move).collect(),
            contour: c.iter().map(Seg::swapped).collect(),
        })
    } else {
        Ok(Pocket { level, finish, contour: c })
    }
}

/// The distance from `p` to a segment.
pub fn distance_to(s: &Seg, p: P) -> f64 {
    match s.arc {
        None => {
            let d = sub(s.end, s.start);
            let t = (dot(sub(p, s.start), d) / dot(d, d)).clamp(0.0, 1.0);
            dist(p, add(s.start, mul(d, t)))
        }
        Some((c, sw)) => {
            let r = s.radius();
            let on = turn(angle(sub(s.start, c)), angle(sub(p, c)), sw.signum()) <= sw.abs();
            if on && dist(p, c) > 0.0 {
                (dist(p, c) - r).abs()
            } else {
                dist(p, s.start).min(dist(p, s.end))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(w: f64, h: f64) -> Vec<Seg> {
        let p = [[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]];
        (0..4).map(|i| Seg::line(p[i], p[(i + 1) % 4])).collect()
    }

    #[test]
    fn a_rectangle_offsets_to_a_smaller_rectangle() {
        let c = offset(&rect(10.0, 6.0), 1.0).unwrap();
        assert_eq!(c.len(), 4);
        let want = [[1.0, 1.0], [9.0, 1.0], [9.0, 5.0], [1.0, 5.0]];
        for (s, w) in c.iter().zip(want) {
            assert!(dist(s.start, w) < 1e-12, "{s:?}");
        }
        // Clockwise too.
        let cw: Vec<Seg> = rect(10.0, 6.0).iter().rev().map(|s| Seg::line(s.end, s.start)).collect();
        let c = offset(&cw, 1.0).unwrap();
        assert!(area(&c) < 0.0 && (area(&c) + 32.0).abs() < 1e-9);
    }

    #[test]
    fn a_concave_corner_becomes_an_arc_about_it() {
        // An L: the corner at (4, 4) is concave.
        let p = [[0.0, 0.0], [10.0, 0.0], [10.0, 4.0], [4.0, 4.0], [4.0, 10.0], [0.0, 10.0]];
        let l: Vec<Seg> = (0..6).map(|i| Seg::line(p[i], p[(i + 1) % 6])).collect();
        let c = offset(&l, 1.0).unwrap();
        let arcs: Vec<_> = c.iter().filter(|s| s.arc.is_some()).collect();
        assert_eq!(arcs.len(), 1);
        let (centre, sweep) = arcs[0].arc.unwrap();
        assert!(dist(centre, [4.0, 4.0]) < 1e-12 && (sweep + PI / 2.0).abs() < 1e-12, "{:?}", arcs[0]);
        assert!(dist(arcs[0].start, [4.0, 3.0]) < 1e-12 && dist(arcs[0].end, [3.0, 4.0]) < 1e-12);
    }

    #[test]
    fn a_concave_start_corner_starts_the_pass_on_its_bisector() {
        // A 40 x 40 square with a half-disc tab (radius 10) on its right edge, started at the
        // tab's lower end (20, 0), a concave corner: up the edge +Y, then the arc leaves +X.
        let tab = Seg { start: [20.0, 0.0], end: [20.0, 20.0], arc: Some(([20.0, 10.0], PI)) };
        let c = [[20.0, 20.0], [-20.0, 20.0], [-20.0, -20.0], [20.0, -20.0], [20.0, 0.0]];
        let mut outline = vec![tab];
        outline.extend(c.windows(2).map(|w| Seg::line(w[0], w[1])));
        let o = offset(&outline, 5.5).unwrap();
        // The tool at d = 5.5 from (20, 0) on the bisector of +X (the arc) and −Y (back along
        // the edge): the direction 135°, (20 − 5.5/√2, 5.5/√2).
        let h = 5.5 / 2f64.sqrt();
        assert!(dist(o[0].start, [20.0 - h, h]) < 1e-12, "{:?}", o[0]);
        // The first half of the arc ends on the tab's offset (radius 4.5 about (20, 10)), the
        // last half starts at the edge's offset (14.5, 0) and closes the pass.
        assert!(dist(o[0].end, [20.0, 5.5]) < 1e-12 && dist(o[o.len() - 1].start, [14.5, 0.0]) < 1e-12);
        assert!(dist(o[o.len() - 1].end, o[0].start) < 1e-12);
        assert!(plan(&outline, [0.0, 0.0], 5.0, 0.5, 8.0, false).is_ok());
    }

    #[test]
    fn a_tool_too_big_or_a_neck_is_refused() {
        assert!(matches!(offset(&rect(10.0, 6.0), 3.0), Err(Refusal::Argument(_))));
        // A dumbbell: two squares joined by a 1 mm corridor.
        let p = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.5],
            [6.0, 1.5],
            [6.0, 0.0],
            [10.0, 0.0],
            [10.0, 4.0],
            [6.0, 4.0],
            [6.0, 2.5],
            [4.0, 2.5],
            [4.0, 4.0],
            [0.0, 4.0],
        ];
        let d: Vec<Seg> = (0..12).map(|i| Seg::line(p[i], p[(i + 1) % 12])).collect();
        assert!(offset(&d, 0.4).is_ok());
        assert!(matches!(offset(&d, 0.8), Err(Refusal::NotBuilt(_))), "{:?}", offset(&d, 0.8));
    }

    #[test]
    fn zigzag_in_a_rectangle() {
        // 10 x 6, tool radius 1, no K, J 1.5: region y 1..5, x 1..9; 4/1.5 → 3 intervals.
        let p = plan(&rect(10.0, 6.0), [5.0, 3.0], 1.0, 0.0, 1.5, true).unwrap();
        let strokes: Vec<P> = p.level.iter().map(Move::to).collect();
        // Entry to (1, 1), the loop, strokes at y = 1 + 4/3 and 1 + 8/3.
        assert!(dist(strokes[0], [1.0, 1.0]) < 1e-12);
        for y in [1.0 + 4.0 / 3.0, 1.0 + 8.0 / 3.0] {
            assert!(strokes.iter().any(|q| (q[1] - y).abs() < 1e-12 && (q[0] - 1.0).abs() < 1e-12));
            assert!(strokes.iter().any(|q| (q[1] - y).abs() < 1e-12 && (q[0] - 9.0).abs() < 1e-12));
        }
        assert_eq!(*strokes.last().unwrap(), [5.0, 3.0]);
        assert!(p.finish.is_empty());
    }

    #[test]
    fn a_start_hole_outside_the_region_is_refused() {
        let r = plan(&rect(10.0, 6.0), [0.5, 3.0], 1.0, 0.0, 1.5, true);
        assert!(matches!(r, Err(Refusal::Argument(_))), "{r:?}");
    }

    #[test]
    fn a_u_shape_with_strokes_across_its_arms_is_refused() {
        let p = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [7.0, 10.0], [7.0, 3.0], [3.0, 3.0], [3.0, 10.0], [0.0, 10.0]];
        let u: Vec<Seg> = (0..8).map(|i| Seg::line(p[i], p[(i + 1) % 8])).collect();
        // Strokes along X cut both arms: several pieces.
        assert!(matches!(plan(&u, [5.0, 1.5], 0.5, 0.0, 1.0, true), Err(Refusal::NotBuilt(_))));
        // Along Y (I) every stroke is one piece.
        assert!(plan(&u, [5.0, 1.5], 0.5, 0.0, 1.0, false).is_ok());
    }
}
