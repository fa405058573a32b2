//! The geometry every layer shares: vectors, rotations by angle, and rigid transforms (a frame
//! inside its parent). Kinematics, tilted planes, setting error compensation and the canonical
//! commands build on it; it depends on nothing of theirs.

use nalgebra::{Matrix3, Vector3};

pub type Vec3 = Vector3<f64>;

/// Rotation by `deg` degrees about coordinate axis `axis` (0 X, 1 Y, 2 Z), right hand, exact
/// at quarter turns.
pub fn axis_rotation(axis: usize, deg: f64) -> Matrix3<f64> {
    let (s, c) = crate::angle::sin_cos_deg(deg);
    match axis {
        0 => Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c),
        1 => Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c),
        _ => Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0),
    }
}

/// A frame inside its parent: the columns of `r` are its X, Y, Z axes, `o` its origin, both in
/// the parent's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rigid {
    pub r: Matrix3<f64>,
    pub o: Vec3,
}

impl Rigid {
    pub fn identity() -> Rigid {
        Rigid { r: Matrix3::identity(), o: Vec3::zeros() }
    }

    /// A point given in this frame, in the parent's coordinates.
    pub fn to_parent(&self, p: &Vec3) -> Vec3 {
        self.o + self.r * p
    }

    /// A point of the parent in this frame's coordinates.
    pub fn from_parent(&self, p: &Vec3) -> Vec3 {
        self.r.transpose() * (p - self.o)
    }

    /// A direction given in this frame, in the parent's coordinates.
    pub fn direction_to_parent(&self, d: &Vec3) -> Vec3 {
        self.r * d
    }

    /// `child`, given inside this frame, as a frame of this frame's parent (G68.4: the new frame
    /// is the old one composed with the commanded one).
    pub fn then(&self, child: &Rigid) -> Rigid {
        Rigid { r: self.r * child.r, o: self.o + self.r * child.o }
    }

    pub fn x(&self) -> Vec3 {
        self.r.column(0).into()
    }

    pub fn y(&self) -> Vec3 {
        self.r.column(1).into()
    }

    pub fn z(&self) -> Vec3 {
        self.r.column(2).into()
    }
}
