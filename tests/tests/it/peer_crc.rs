//! Cutter compensation C against a real peer: LinuxCNC's interpreter `rs274` (fetched into
//! `.peer/` by `scripts/peer-rs274.sh`, which `scripts/test.sh` runs before these tests)
//! compensates the same programs, and fivex's tool centre path (`fivex interp --stages`) must
//! end every offset-mode move where rs274's does, to the four decimals rs274 prints. The
//! programs are random convex pockets of straight sides and random rounded-rectangle pockets
//! (tangent arcs), cut inside with G41 — the cases where FANUC's type C and LinuxCNC compute the
//! same points by their rules (`docs/cutter-compensation.md`, "Peer: LinuxCNC"): the start-up
//! block and every corner. The block before the G40 block and the cancel itself are left out:
//! there the two differ by design (LinuxCNC ends at the perpendicular vector, FANUC's type A at
//! the intersection). Outside corners are not compared (LinuxCNC inserts an arc).
//!
//! Ignored in a plain `cargo test` (it needs the peer on the machine); `scripts/test.sh`
//! installs the peer and runs it with `--ignored`. Run by hand:
//! `bash scripts/peer-rs274.sh && cargo build -p fivex-server --bin fivex &&
//! cargo test -p fivex-e2e --test it peer_crc -- --ignored`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::common::{fivex, stdout};

/// The tool radius (D1), mm.
const RADIUS: f64 = 5.0;
/// rs274 prints four decimals.
const TOLERANCE: f64 = 1e-4;

/// A small deterministic generator (xorshift64*), so that the programs are the same each run.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

fn peer_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../.peer")
}

/// rs274's tool centre end points of the feed moves (lines and arcs) of `program`, in order.
fn rs274(program: &str, work: &Path) -> Vec<[f64; 2]> {
    let lcnc = peer_dir().join("linuxcnc");
    let bin = lcnc.join("usr/bin/rs274");
    assert!(bin.is_file(), "LinuxCNC's rs274 is not installed: run `bash scripts/peer-rs274.sh` first");
    // The standalone rs274 reads its tool table in inches: T1 is 10 mm across.
    let table = work.join("tool.tbl");
    std::fs::write(&table, format!("T1 P1 D{} Z0 ;\n", 2.0 * RADIUS / 25.4)).unwrap();
    let ngc = work.join("program.ngc");
    std::fs::write(&ngc, program).unwrap();
    let trace = work.join("trace.txt");
    let libs = format!("{}:{}", lcnc.join("usr/lib").display(), lcnc.join("usr/lib/linuxcnc").display());
    // One rs274 at a time (the test threads run side by side; it keeps files of its own).
    static ONE: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _one = ONE.lock().unwrap_or_else(|e| e.into_inner());
    let mut child = Command::new(&bin)
        .current_dir(work)
        .env("LD_LIBRARY_PATH", libs)
        .arg("-t")
        .arg(&table)
        .arg(&ngc)
        .arg(&trace)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("rs274 starts");
    // It asks on stderr what to do; "1" starts interpreting.
    std::io::Write::write_all(child.stdin.as_mut().unwrap(), b"1\n").unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "rs274 refused the program:\n{}\n{program}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&trace).unwrap();
    text.lines()
        .filter_map(|l| {
            let args = l.split_once("STRAIGHT_FEED(").or_else(|| l.split_once("ARC_FEED("))?.1;
            let mut numbers = args.split(',').map(|x| x.trim().trim_end_matches(')').parse::<f64>().unwrap());
            Some([numbers.next()?, numbers.next()?])
        })
        .collect()
}

/// fivex's tool centre end points of the feed moves of `program`, in order.
fn fivex_centre(program: &str, work: &Path) -> Vec<[f64; 2]> {
    let path = work.join("program.nc");
    std::fs::write(&path, program).unwrap();
    let out = fivex(&["interp", "--stages", path.to_str().unwrap()]);
    assert!(out.status.success(), "fivex refused the program:\n{}\n{program}", crate::common::stderr(&out));
    stdout(&out)
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .filter(|c| c["type"] == "motion" && c["motion"] != "rapid")
        .map(|c| [c["target"]["X"].as_f64().unwrap(), c["target"]["Y"].as_f64().unwrap()])
        .collect()
}

/// Both tool centre paths, equal to [`TOLERANCE`] but for the last two moves (the block before
/// the cancel, and the cancel).
fn assert_agree(program: &str) {
    let work = tempfile::tempdir().unwrap();
    let (theirs, ours) = (rs274(program, work.path()), fivex_centre(program, work.path()));
    assert_eq!(theirs.len(), ours.len(), "feed moves: rs274 {theirs:?}\nfivex {ours:?}\n{program}");
    assert!(ours.len() > 2, "nothing to compare\n{program}");
    for (k, (a, b)) in theirs.iter().zip(&ours).take(ours.len() - 2).enumerate() {
        let off = (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
        assert!(off <= TOLERANCE, "move {k}: rs274 {a:?}, fivex {b:?} ({off:.6} mm apart)\n{program}");
    }
}

const HEAD: &str = "G21 G17 G40 G90 G94\nT1 M6\n";

/// A convex pocket: corners on an ellipse at sorted random angles, cut counter-clockwise with
/// G41; `None` where a side's offset would vanish (the offset path would then
/// drop it: no longer a like-for-like comparison).
fn convex_pocket(rng: &mut Rng) -> Option<String> {
    let (a, b) = (rng.between(30.0, 70.0), rng.between(30.0, 70.0));
    let n = 3 + (rng.unit() * 6.0) as usize;
    let mut angles: Vec<f64> = (0..n).map(|_| rng.between(0.0, std::f64::consts::TAU)).collect();
    angles.sort_by(f64::total_cmp);
    let corners: Vec<[f64; 2]> = angles.iter().map(|t| [round3(a * t.cos()), round3(b * t.sin())]).collect();
    // Each side keeps a length after the offset: L > r (cot α/2 + cot β/2) with some room.
    let interior = |k: usize| {
        let (p, q, r) = (corners[(k + n - 1) % n], corners[k], corners[(k + 1) % n]);
        let (u, v) = ([p[0] - q[0], p[1] - q[1]], [r[0] - q[0], r[1] - q[1]]);
        angle_between(u, v)
    };
    for k in 0..n {
        let next = (k + 1) % n;
        let side = dist(corners[k], corners[next]);
        let lost = RADIUS * (1.0 / (interior(k) / 2.0).tan() + 1.0 / (interior(next) / 2.0).tan());
        if side < lost + 2.0 || interior(k) < 0.35 {
            return None;
        }
    }
    // The start-up runs square onto the middle of the last side, from two radii inside (a
    // start-up at a slant ends where its offset meets the side's: far along it, or past it).
    let last = corners[n - 1];
    let mid = [round3((last[0] + corners[0][0]) / 2.0), round3((last[1] + corners[0][1]) / 2.0)];
    let along = [corners[0][0] - last[0], corners[0][1] - last[1]];
    let length = along[0].hypot(along[1]);
    let inward = [-along[1] / length, along[0] / length];
    let from = [round3(mid[0] + 2.0 * RADIUS * inward[0]), round3(mid[1] + 2.0 * RADIUS * inward[1])];
    let inside = (0..n).all(|k| {
        let (p, q) = (corners[k], corners[(k + 1) % n]);
        let offset = ((q[0] - p[0]) * (from[1] - p[1]) - (q[1] - p[1]) * (from[0] - p[0])) / dist(p, q);
        offset > RADIUS
    });
    // Each half of the last side keeps a length too: the start-up's square corner takes a
    // radius of it, the pocket's corner at its other end r cot α/2.
    let cot_half = |k: usize| 1.0 / (interior(k) / 2.0).tan();
    let half_lost = RADIUS * (1.0 + cot_half(0).max(cot_half(n - 1)));
    if !inside || length / 2.0 < half_lost + 2.0 {
        return None;
    }
    let mut p = format!("{HEAD}G00 X{:.3} Y{:.3} Z0.\n", from[0], from[1]);
    p += &format!("G41 D1 G01 X{:.3} Y{:.3} F1000.\n", mid[0], mid[1]);
    for c in &corners {
        p += &format!("X{:.3} Y{:.3}\n", c[0], c[1]);
    }
    p += &format!("X{:.3} Y{:.3}\nG40 X{:.3} Y{:.3}\nM2\n", mid[0], mid[1], from[0], from[1]);
    Some(p)
}

/// A rectangular pocket with rounded corners (tangent arcs of a radius larger than the tool's),
/// cut counter-clockwise with G41 from its middle, square onto the middle of its lower side.
fn rounded_pocket(rng: &mut Rng) -> String {
    let (w, h) = (rng.between(40.0, 90.0), rng.between(30.0, 90.0));
    // The first side, from the start-up's end at its middle, is longer than the radius: the
    // start-up ends where the offsets meet, a radius along it.
    let rc = round3(rng.between(RADIUS + 1.0, (w / 2.0 - RADIUS - 2.0).min(h / 2.0 - 2.0)));
    let (x0, y0, x1, y1) = (round3(-w / 2.0), round3(-h / 2.0), round3(w / 2.0), round3(h / 2.0));
    let mut p = format!("{HEAD}G00 X0. Y0. Z0.\nG41 D1 G01 X0. Y{y0:.3} F1000.\n");
    p += &format!("X{:.3}\nG03 X{x1:.3} Y{:.3} R{rc:.3}\n", x1 - rc, y0 + rc);
    p += &format!("G01 Y{:.3}\nG03 X{:.3} Y{y1:.3} R{rc:.3}\n", y1 - rc, x1 - rc);
    p += &format!("G01 X{:.3}\nG03 X{x0:.3} Y{:.3} R{rc:.3}\n", x0 + rc, y1 - rc);
    p += &format!("G01 Y{:.3}\nG03 X{:.3} Y{y0:.3} R{rc:.3}\n", y0 + rc, x0 + rc);
    p += "G01 X0.\nG40 X0. Y0.\nM2\n";
    p
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

fn angle_between(u: [f64; 2], v: [f64; 2]) -> f64 {
    (u[0] * v[1] - u[1] * v[0]).abs().atan2(u[0] * v[0] + u[1] * v[1])
}

#[test]
#[ignore = "needs LinuxCNC's rs274 (scripts/peer-rs274.sh); scripts/test.sh runs it"]
fn random_convex_pockets_agree_with_linuxcnc() {
    let mut rng = Rng(0x5eed_c0de_0017_0020);
    let mut compared = 0;
    for _ in 0..100 {
        if let Some(program) = convex_pocket(&mut rng) {
            assert_agree(&program);
            compared += 1;
        }
    }
    // The filter must leave enough of them to compare.
    assert!(compared >= 40, "only {compared} of 100 random pockets compared");
}

#[test]
#[ignore = "needs LinuxCNC's rs274 (scripts/peer-rs274.sh); scripts/test.sh runs it"]
fn random_rounded_pockets_agree_with_linuxcnc() {
    let mut rng = Rng(0x0a5c_0f00_dead_beef);
    for _ in 0..30 {
        assert_agree(&rounded_pocket(&mut rng));
    }
}

#[test]
#[ignore = "needs LinuxCNC's rs274 (scripts/peer-rs274.sh); scripts/test.sh runs it"]
fn a_disagreement_is_found() {
    // The comparison can fail: a pocket whose corner moves by 0.001 mm in fivex's copy only
    // (rs274 and fivex read different texts here on purpose).
    let work = tempfile::tempdir().unwrap();
    let text = format!("{HEAD}G00 X20. Y20. Z0.\nG41 D1 G01 Y0. F1000.\nX40.\nY40.\nX0.\nY0.\nX20.\nG40 Y20.\nM2\n");
    let theirs = rs274(&text, work.path());
    let ours = fivex_centre(&text.replace("Y40.", "Y40.001"), work.path());
    assert_eq!(theirs.len(), ours.len());
    let worst = theirs.iter().zip(&ours).map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs())).fold(0.0, f64::max);
    assert!(worst > TOLERANCE, "a moved corner went unnoticed");
}
