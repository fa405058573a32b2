//! Tilted working plane frames: the feature coordinate system (FCS) that G68.2, G68.3 and G68.4
//! define inside the workpiece coordinate system (spec `fanuc-twp-wsec-manual-params.md` §2.2–
//! §2.8, TWP-01…TWP-10). Pure geometry: the interpreter decides which form a block uses and
//! checks its words; the conventions the seed leaves open are the extract's engine defaults
//! (fixed-axis roll–pitch–yaw, OQ-02; three-point shift along the FCS axes before R, OQ-03;
//! projection angles right-hand about the WCS axes, OQ-05; antiparallel projection vectors
//! refused, OQ-06) and are tested as such.

use crate::alarm::AlarmId;
use crate::geom::{axis_rotation, Rigid, Vec3};
use nalgebra::Matrix3;
/// PS5457 (FANUC) / COR-141 (Syntec).
const FORMAT: AlarmId = AlarmId::TwpFormat;

/// What the tilted-plane forms build frames with.
impl Rigid {
    fn from_axes(x: Vec3, y: Vec3, z: Vec3, o: Vec3) -> Rigid {
        Rigid { r: Matrix3::from_columns(&[x, y, z]), o }
    }

    /// Turned about its own Z axis by `deg` (the R of three points, K of projection angles).
    fn turned_about_z(&self, deg: f64) -> Rigid {
        Rigid { r: self.r * rz(deg), o: self.o }
    }
}

fn rx(deg: f64) -> Matrix3<f64> {
    axis_rotation(0, deg)
}

fn ry(deg: f64) -> Matrix3<f64> {
    axis_rotation(1, deg)
}

fn rz(deg: f64) -> Matrix3<f64> {
    axis_rotation(2, deg)
}

/// G68.2 (no P): Euler angles Z–X–Z, intrinsic: R = Rz(I)·Rx(J)·Rz(K) (§2.3).
pub fn euler(origin: Vec3, i: f64, j: f64, k: f64) -> Rigid {
    Rigid { r: rz(i) * rx(j) * rz(k), o: origin }
}

/// G68.2 P1: roll I about X, pitch J about Y, yaw K about Z, in the order Q (digits 1 = X, 2 =
/// Y, 3 = Z, first rotation first; default 123) about the fixed WCS axes, so each later
/// rotation multiplies on the left (§2.4).
pub fn roll_pitch_yaw(origin: Vec3, q: Option<u32>, i: f64, j: f64, k: f64) -> Result<Rigid, AlarmId> {
    let about = |digit: u32| match digit {
        1 => rx(i),
        2 => ry(j),
        _ => rz(k),
    };
    let order = q.unwrap_or(123);
    if ![123, 132, 213, 321, 231, 312].contains(&order) {
        return Err(FORMAT);
    }
    let (a, b, c) = (order / 100, order / 10 % 10, order % 10);
    Ok(Rigid { r: about(c) * about(b) * about(a), o: origin })
}

/// G68.2 P2: three points — P1 the origin, P2 on +X, P3 in the XY plane on the +Y side; the
/// origin is then shifted by `shift` along the FCS axes and the frame turned by `r` degrees about
/// its Z (§2.5). Refused when two points coincide, the points are collinear, or a point lies
/// nearer than `min_distance` (FANUC No.11220) to the line through the other two.
pub fn three_points(p: [Vec3; 3], shift: Vec3, r: f64, min_distance: f64) -> Result<Rigid, AlarmId> {
    for (a, b, c) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
        let line = p[b] - p[a];
        if line.norm() == 0.0 {
            return Err(FORMAT);
        }
        let distance = line.cross(&(p[c] - p[a])).norm() / line.norm();
        if distance == 0.0 || distance < min_distance {
            return Err(FORMAT);
        }
    }
    let x = (p[1] - p[0]).normalize();
    let z = (p[1] - p[0]).cross(&(p[2] - p[0])).normalize();
    let axes = Rigid::from_axes(x, z.cross(&x), z, p[0]);
    let shifted = Rigid { o: axes.to_parent(&shift), ..axes };
    Ok(shifted.turned_about_z(r))
}

/// G68.2 P3: two vectors — `x` the FCS +X, `z` the FCS +Z, at 85°…95° to each other; the frame
/// keeps Z exactly and makes X perpendicular to it (Z is the tool axis) (§2.6).
pub fn two_vectors(origin: Vec3, x: Vec3, z: Vec3) -> Result<Rigid, AlarmId> {
    two_vectors_within(origin, x, z, 5.0)
}

/// Two vectors at 90° ± `tolerance_deg` to each other (Syntec's teach screen, `crate::teach`,
/// has a tolerance of its own), built as [`two_vectors`] builds them.
pub fn two_vectors_within(origin: Vec3, x: Vec3, z: Vec3, tolerance_deg: f64) -> Result<Rigid, AlarmId> {
    if x.norm() == 0.0 || z.norm() == 0.0 {
        return Err(FORMAT);
    }
    let angle = (x.dot(&z) / (x.norm() * z.norm())).clamp(-1.0, 1.0).acos().to_degrees();
    if !(90.0 - tolerance_deg..=90.0 + tolerance_deg).contains(&angle) {
        return Err(FORMAT);
    }
    let zc = z.normalize();
    let xc = (x - zc * x.dot(&zc)).normalize();
    Ok(Rigid::from_axes(xc, zc.cross(&xc), zc, origin))
}

/// G68.2 P4: projection angles — the WCS X axis turned about Y by `i` gives A, the WCS Y axis
/// turned about X by `j` gives B; the plane holds A (its X) and B, and is turned by `k` about
/// its Z (§2.7). Refused when A and B are within 1° of parallel or antiparallel.
pub fn projection(origin: Vec3, i: f64, j: f64, k: f64) -> Result<Rigid, AlarmId> {
    let a = ry(i) * Vec3::x();
    let b = rx(j) * Vec3::y();
    let angle = a.dot(&b).clamp(-1.0, 1.0).acos().to_degrees();
    if !(1.0..=179.0).contains(&angle) {
        return Err(FORMAT);
    }
    let z = a.cross(&b).normalize();
    let x = a.normalize();
    Ok(Rigid::from_axes(x, z.cross(&x), z, origin).turned_about_z(k))
}

/// G68.3: the FCS +Z is the tool axis `tool` (in the WCS); X is perpendicular to `vertical`
/// (FANUC No.12321: the WCS axis taken as vertical) and to Z, X = vertical × Z; turned by `r`
/// about Z (§2.8). When the tool is parallel to the vertical axis (within `parallel_deg`,
/// No.12322) X is the fallback axis of §2.15: +Y for a vertical X, +Z for Y, +X for Z.
pub fn tool_axis(origin: Vec3, tool: Vec3, vertical: Vec3, r: f64, parallel_deg: f64) -> Result<Rigid, AlarmId> {
    let z = tool.try_normalize(1e-12).ok_or(FORMAT)?;
    let v = vertical.try_normalize(1e-12).ok_or(FORMAT)?;
    let angle = z.dot(&v).abs().min(1.0).acos().to_degrees();
    let x = if angle <= parallel_deg.max(1e-9) {
        let fallback = if v.x.abs() > 0.5 {
            Vec3::y()
        } else if v.y.abs() > 0.5 {
            Vec3::z()
        } else {
            Vec3::x()
        };
        (fallback - z * fallback.dot(&z)).normalize()
    } else {
        v.cross(&z).normalize()
    };
    Ok(Rigid::from_axes(x, z.cross(&x), z, origin).turned_about_z(r))
}

#[cfg(test)]
mod tests;
