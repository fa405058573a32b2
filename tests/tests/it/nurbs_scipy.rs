//! G06.2 against an independent evaluator: SciPy's B-splines (`scripts/nurbs_reference.py`).
//! Every chord vertex `fivex interp` prints for a curve lies on the rational curve SciPy
//! evaluates from the same control points, weights and knots within 1e-9 mm, the path ends
//! where the curve does, and the curve's first and second derivatives the engine computes
//! (`fivex_engine::nurbs::Curve::derivatives`) are SciPy's
//! within 1e-9 of their size. Needs python3 with SciPy (Debian's python3-scipy): ignored by a plain
//! `cargo test`, run by scripts/test.sh, which installs it.

use crate::common::{fivex_in, stdout};
use serde_json::{json, Value};
use std::io::Write;
use std::process::{Command, Stdio};

/// A curve: rank (order), knots, control points and weights.
struct Curve {
    rank: usize,
    knots: Vec<f64>,
    points: Vec<[f64; 3]>,
    weights: Vec<f64>,
}

impl Curve {
    /// The program: move to the first point, the curve, then G01 there. Every number is printed
    /// with six decimals (FANUC takes no more digits): the curve's values are given so.
    fn program(&self) -> String {
        let p0 = self.points[0];
        let mut text = format!("G90 G17 G00 X{:.6} Y{:.6} Z{:.6}\n", p0[0], p0[1], p0[2]);
        let n = self.points.len();
        for (i, (p, w)) in self.points.iter().zip(&self.weights).enumerate() {
            let head = if i == 0 { format!("G06.2 P{} ", self.rank) } else { String::new() };
            let feed = if i == 0 { " F1000" } else { "" };
            text += &format!("{head}K{:.6} X{:.6} Y{:.6} Z{:.6} R{:.6}{feed}\n", self.knots[i], p[0], p[1], p[2], w);
        }
        for k in &self.knots[n..] {
            text += &format!("K{k:.6}\n");
        }
        let last = self.points[n - 1];
        text + &format!("G01 X{:.6} Y{:.6} Z{:.6}\nM30\n", last[0], last[1], last[2])
    }
}

/// The X/Y/Z every motion of `fivex interp` ends at (mill3: machine = programmed here).
fn vertices(program: &str) -> Vec<[f64; 3]> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.nc"), program).unwrap();
    let out = fivex_in(dir.path(), &["interp", "p.nc", "--preset", "mill3"]);
    assert!(out.status.success(), "{}\n{program}", String::from_utf8_lossy(&out.stderr));
    stdout(&out)
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|v| v["type"] == "motion")
        .map(|v| ["X", "Y", "Z"].map(|a| v["machine"][a].as_f64().unwrap()))
        .collect()
}

/// A point of a curve and its first and second derivatives.
type Derivatives = [[f64; 3]; 3];

/// SciPy's verdict on `samples`: the largest distance to the curve and its two ends; and at
/// each parameter of `at`, the curve's point and first and second derivatives.
fn reference(curve: &Curve, samples: &[[f64; 3]], at: &[f64]) -> (f64, [[f64; 3]; 2], Vec<Derivatives>) {
    let job = json!({
        "degree": curve.rank - 1,
        "knots": curve.knots,
        "points": curve.points,
        "weights": curve.weights,
        "samples": samples,
        "at": at,
    });
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../scripts/nurbs_reference.py");
    // Debian's python3-scipy is for the system's interpreter (a python3 earlier on PATH may not
    // see it).
    let python = if std::path::Path::new("/usr/bin/python3").exists() { "/usr/bin/python3" } else { "python3" };
    let mut child = Command::new(python)
        .arg(script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("python3 (with SciPy: apt install python3-scipy)");
    child.stdin.take().unwrap().write_all(job.to_string().as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "the reference script failed");
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let end = |k: usize| [0, 1, 2].map(|i| v["ends"][k][i].as_f64().unwrap());
    let triple = |d: &Value| [0, 1, 2].map(|k| [0, 1, 2].map(|i| d[k][i].as_f64().unwrap()));
    let derivatives = v["derivatives"].as_array().unwrap().iter().map(triple).collect();
    (v["max"].as_f64().unwrap(), [end(0), end(1)], derivatives)
}

fn assert_on_curve(curve: &Curve) {
    let program = curve.program();
    let xs = vertices(&program);
    // The rapid to the first point, then the chords; the closing G01 is a move of length 0.
    let chords: Vec<[f64; 3]> = xs[1..].to_vec();
    assert!(chords.len() > 20, "{} chord vertices\n{program}", chords.len());
    // The engine's curve of the same numbers, and 50 parameters across its domain (inside
    // each knot span: a derivative is one-sided at a knot of multiplicity).
    let engine = fivex_engine::nurbs::Curve::<3>::new(
        curve.rank,
        curve.knots.clone(),
        curve.points.clone(),
        curve.weights.clone(),
    )
    .unwrap();
    let (lo, hi) = engine.domain();
    let at: Vec<f64> = (0..50).map(|i| lo + (hi - lo) * (i as f64 + 0.37) / 50.0).collect();
    let (worst, ends, derivatives) = reference(curve, &chords, &at);
    assert!(worst < 1e-9, "a vertex is {worst} mm off SciPy's curve\n{program}");
    let last = chords.last().unwrap();
    let gap = (0..3).map(|i| (last[i] - ends[1][i]).powi(2)).sum::<f64>().sqrt();
    assert!(gap < 1e-9, "the path ends {gap} mm from the curve's end\n{program}");
    for (u, want) in at.iter().zip(&derivatives) {
        let got = engine.derivatives(*u);
        for d in 0..3 {
            let size = want[d].iter().map(|x| x * x).sum::<f64>().sqrt().max(1.0);
            let off = (0..3).map(|i| (got[d][i] - want[d][i]).powi(2)).sum::<f64>().sqrt();
            assert!(off <= 1e-9 * size, "derivative {d} at u = {u}: {:?} against SciPy's {:?}", got[d], want[d]);
        }
    }
}

#[test]
#[ignore = "needs python3 with SciPy (apt install python3-scipy); scripts/test.sh runs it"]
fn g06_2_agrees_with_scipy() {
    // √2/2 as the program writes it (the circles are then within 1e-7 of exact; the comparison
    // is with the curve of these weights).
    let h = (std::f64::consts::FRAC_1_SQRT_2 * 1e6).round() / 1e6;
    // A quarter circle: a rational quadratic.
    assert_on_curve(&Curve {
        rank: 3,
        knots: vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        points: vec![[10.0, 0.0, 0.0], [10.0, 10.0, 0.0], [0.0, 10.0, 0.0]],
        weights: vec![1.0, h, 1.0],
    });
    // A full circle of nine control points.
    assert_on_curve(&Curve {
        rank: 3,
        knots: vec![0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 4.0, 4.0, 4.0],
        points: vec![
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.0],
            [0.0, 10.0, 0.0],
            [-10.0, 10.0, 0.0],
            [-10.0, 0.0, 0.0],
            [-10.0, -10.0, 0.0],
            [0.0, -10.0, 0.0],
            [10.0, -10.0, 0.0],
            [10.0, 0.0, 0.0],
        ],
        weights: vec![1.0, h, 1.0, h, 1.0, h, 1.0, h, 1.0],
    });
    // A non-rational cubic in space with uneven interior knots.
    assert_on_curve(&Curve {
        rank: 4,
        knots: vec![0.0, 0.0, 0.0, 0.0, 0.7, 1.9, 3.0, 3.0, 3.0, 3.0],
        points: vec![
            [0.0, 0.0, 0.0],
            [5.0, 12.0, 1.0],
            [15.0, -4.0, 3.0],
            [22.0, 9.0, -2.0],
            [30.0, 1.0, 0.5],
            [41.0, 6.0, 2.0],
        ],
        weights: vec![1.0; 6],
    });
    // A rational cubic with uneven weights and a knot of multiplicity two.
    assert_on_curve(&Curve {
        rank: 4,
        knots: vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0],
        points: vec![
            [0.0, 0.0, 0.0],
            [3.0, 8.0, 0.0],
            [9.0, 9.0, 2.0],
            [14.0, 2.0, 4.0],
            [18.0, -3.0, 1.0],
            [25.0, 0.0, 0.0],
        ],
        weights: vec![1.0, 0.4, 2.5, 0.8, 1.7, 1.0],
    });
}
