//! Hill-frame conventions.
//!
//! relnav works internally in one **canonical Hill frame** (also called LVLH / RSW):
//! origin at the target's centre of mass, `x` radial outward (from the Earth's centre
//! through the target), `y` along-track (in the direction of flight, completing the
//! triad), `z` along the orbit normal (the target's orbital angular momentum).
//!
//! The papers use three different conventions (see `../shared/docs/seed-digest.md`,
//! "The four papers use three different Hill-frame conventions"). Every interface that
//! takes or returns positions, velocities, thrust or angles names a [`Frame`]; the
//! conversion is a signed permutation `T` (orthogonal, `det T = +1`), applied as
//! `v_io = T v_canonical` and `v_canonical = T^T v_io`.
//!
//! | code | [`Frame`] | x | y | z | used by |
//! |---|---|---|---|---|---|
//! | 1 | `RadialAlongNormal` | radial out | along-track | orbit normal | canonical; paper 002 |
//! | 2 | `AlongRadialAntinormal` | along-track | radial out | minus orbit normal | paper 000 |
//! | 3 | `AlongAntinormalNadir` | along-track | minus orbit normal | nadir | paper 003 |

use crate::types::{Mat3, Mat6, State, Vec3};

/// A Hill-frame convention for input and output (codes are stable and used by the C ABI
/// and the FMU's `frame` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum Frame {
    /// Canonical: x radial outward, y along-track, z orbit normal (paper 002's frame).
    #[default]
    RadialAlongNormal = 1,
    /// Paper 000: x along-track, y radial outward, z minus orbit normal.
    AlongRadialAntinormal = 2,
    /// Paper 003: x along-track, y minus orbit normal, z nadir (toward the Earth's centre).
    AlongAntinormalNadir = 3,
}

impl Frame {
    /// All conventions, in code order.
    pub const ALL: [Frame; 3] = [
        Frame::RadialAlongNormal,
        Frame::AlongRadialAntinormal,
        Frame::AlongAntinormalNadir,
    ];

    /// The frame with the given stable code, or `None` for an unknown code.
    pub fn from_code(code: i32) -> Option<Frame> {
        match code {
            1 => Some(Frame::RadialAlongNormal),
            2 => Some(Frame::AlongRadialAntinormal),
            3 => Some(Frame::AlongAntinormalNadir),
            _ => None,
        }
    }

    /// The stable code of this frame.
    pub fn code(self) -> i32 {
        self as i32
    }

    /// Short snake-case name (`radial_along_normal`, ...), as used in the FMU.
    pub fn name(self) -> &'static str {
        match self {
            Frame::RadialAlongNormal => "radial_along_normal",
            Frame::AlongRadialAntinormal => "along_radial_antinormal",
            Frame::AlongAntinormalNadir => "along_antinormal_nadir",
        }
    }

    /// The rotation `T` with `v_io = T v_canonical` (rows are the I/O axes expressed in
    /// canonical coordinates).
    pub fn rotation(self) -> Mat3 {
        match self {
            Frame::RadialAlongNormal => Mat3::identity(),
            // x_io = along = y_c, y_io = radial = x_c, z_io = -normal = -z_c
            Frame::AlongRadialAntinormal => Mat3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0),
            // x_io = along = y_c, y_io = -normal = -z_c, z_io = nadir = -x_c
            Frame::AlongAntinormalNadir => Mat3::new(0.0, 1.0, 0.0, 0.0, 0.0, -1.0, -1.0, 0.0, 0.0),
        }
    }

    /// The 6x6 block-diagonal rotation `diag(T, T)` acting on a state `(r, v)`.
    pub fn rotation6(self) -> Mat6 {
        let t = self.rotation();
        let mut m = Mat6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&t);
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&t);
        m
    }

    /// Vector from canonical to this frame: `v_io = T v_c`.
    pub fn vec_from_canonical(self, v: &Vec3) -> Vec3 {
        self.rotation() * v
    }

    /// Vector from this frame to canonical: `v_c = T^T v_io`.
    pub fn vec_to_canonical(self, v: &Vec3) -> Vec3 {
        self.rotation().transpose() * v
    }

    /// State `(r, v)` from canonical to this frame, `x_io = diag(T, T) x_c`, read as the
    /// signed permutation of [`Frame::axis_map`]: `x_io,i = s x_c,j` (plus `0.0`, so that a
    /// zero comes out `+0.0` as from the full product). Equal to `rotation6() * x` bit for bit
    /// for every finite state (tested) but one corner: a zero component the full product
    /// gives as `-0.0` (when all six of its terms are `-0.0`: the other five components
    /// negative or `-0.0`) comes out `+0.0`. Six loads instead of the product's 36
    /// multiplications, on every output of the navigator, the C ABI and the FMU.
    pub fn state_from_canonical(self, x: &State) -> State {
        let m = self.state_map();
        State::from_fn(|i, _| {
            let (j, s) = m[i];
            s * x[j] + 0.0
        })
    }

    /// State `(r, v)` from this frame to canonical.
    pub fn state_to_canonical(self, x: &State) -> State {
        self.rotation6().transpose() * x
    }

    /// Covariance from canonical to this frame: `P_io = T6 P_c T6^T`.
    pub fn cov_from_canonical(self, p: &Mat6) -> Mat6 {
        let t = self.rotation6();
        t * p * t.transpose()
    }

    /// For each axis `i` of this frame, the canonical axis `j` and the sign `s` with
    /// `e_i = s e_j^c`: the three conventions are signed axis permutations (`rotation`,
    /// one non-zero `±1` per row; `tests::rotations_are_signed_permutations`).
    pub fn axis_map(self) -> [(usize, f64); 3] {
        match self {
            Frame::RadialAlongNormal => [(0, 1.0), (1, 1.0), (2, 1.0)],
            Frame::AlongRadialAntinormal => [(1, 1.0), (0, 1.0), (2, -1.0)],
            Frame::AlongAntinormalNadir => [(1, 1.0), (2, -1.0), (0, -1.0)],
        }
    }

    /// [`Frame::axis_map`] for the six state components `(r, v)`: for each component `i`
    /// of this frame the canonical component `j` and the sign `s` with `x_io,i = s x_c,j`
    /// (the velocity block is the position block shifted by 3).
    fn state_map(self) -> [(usize, f64); 6] {
        let m = self.axis_map();
        core::array::from_fn(|i| {
            let (j, s) = m[i % 3];
            (j + 3 * (i / 3), s)
        })
    }

    /// The diagonal of [`Frame::cov_from_canonical`] alone: `(T6 P_c T6^T)_ii = s^2 P_c,jj`
    /// with `(j, s)` from [`Frame::axis_map`], i.e. the permuted diagonal of `P_c`, the
    /// same bits as the full congruence's diagonal for a finite `P_c`. The 1-sigma
    /// outputs of the navigator, the C ABI and the FMU need only these (six loads
    /// instead of the full congruence's 432 multiplications).
    pub fn variances_from_canonical(self, p: &Mat6) -> [f64; 6] {
        let m = self.state_map();
        core::array::from_fn(|i| {
            let (j, s) = m[i];
            s * p[(j, j)] * s
        })
    }

    /// Covariance from this frame to canonical: `P_c = T6^T P_io T6`.
    pub fn cov_to_canonical(self, p: &Mat6) -> Mat6 {
        let t = self.rotation6();
        t.transpose() * p * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The permuted state equals the full product `diag(T, T) x`, zeros included.
    #[test]
    fn state_from_canonical_is_the_full_product() {
        let xs = [
            State::from_row_slice(&[400.0, -500.0, 200.0, 0.0, -0.0, 1e-3]),
            State::from_row_slice(&[-1.5, 2.5e-9, -3.0e7, 4.0, -5.0, 6.0]),
            State::zeros(),
        ];
        for f in Frame::ALL {
            for x in &xs {
                let full = f.rotation6() * x;
                let got = f.state_from_canonical(x);
                for (a, b) in got.iter().zip(full.iter()) {
                    assert_eq!(a.to_bits(), b.to_bits(), "{f:?} {x}");
                }
            }
        }
    }

    /// `axis_map` is `rotation`, read as a signed permutation.
    #[test]
    fn rotations_are_signed_permutations() {
        for f in [
            Frame::RadialAlongNormal,
            Frame::AlongRadialAntinormal,
            Frame::AlongAntinormalNadir,
        ] {
            let t = f.rotation();
            let m = f.axis_map();
            for i in 0..3 {
                for j in 0..3 {
                    let want = if m[i].0 == j { m[i].1 } else { 0.0 };
                    assert_eq!(t[(i, j)], want, "{f:?} ({i}, {j})");
                }
            }
        }
    }

    /// The variances alone equal the full congruence's diagonal bit for bit, in every
    /// convention, for a dense covariance.
    #[test]
    fn variances_are_the_diagonal_of_the_full_conversion() {
        let a = Mat6::from_fn(|i, j| {
            ((i * 7 + j * 3) % 11) as f64 * 0.37 - 1.1 + (i == j) as u8 as f64 * 9.0
        });
        let p = a * a.transpose();
        for f in [
            Frame::RadialAlongNormal,
            Frame::AlongRadialAntinormal,
            Frame::AlongAntinormalNadir,
        ] {
            let full = f.cov_from_canonical(&p);
            let d = f.variances_from_canonical(&p);
            for i in 0..6 {
                assert_eq!(d[i].to_bits(), full[(i, i)].to_bits(), "{f:?} {i}");
            }
        }
    }
    use crate::dynamics::CwModel;

    #[test]
    fn rotations_are_proper() {
        for f in Frame::ALL {
            let t = f.rotation();
            assert!((t * t.transpose() - Mat3::identity()).norm() < 1e-15);
            assert!(
                (t.determinant() - 1.0).abs() < 1e-15,
                "{f:?} is not right-handed"
            );
            assert_eq!(Frame::from_code(f.code()), Some(f));
        }
        assert_eq!(Frame::from_code(0), None);
        assert_eq!(Frame::from_code(4), None);
    }

    #[test]
    fn round_trip() {
        let x = State::from_row_slice(&[1.0, -2.0, 3.5, 0.1, 0.2, -0.3]);
        let mut p = Mat6::from_fn(|i, j| 1.0 / (1.0 + i as f64 + j as f64));
        p += Mat6::identity();
        for f in Frame::ALL {
            let back = f.state_to_canonical(&f.state_from_canonical(&x));
            assert!((back - x).norm() < 1e-15);
            let pb = f.cov_to_canonical(&f.cov_from_canonical(&p));
            assert!((pb - p).norm() < 1e-15);
        }
    }

    #[test]
    fn named_axes() {
        // canonical unit vectors: radial, along-track, normal
        let radial = Vec3::new(1.0, 0.0, 0.0);
        let along = Vec3::new(0.0, 1.0, 0.0);
        let normal = Vec3::new(0.0, 0.0, 1.0);
        let f = Frame::AlongRadialAntinormal;
        assert_eq!(f.vec_from_canonical(&along), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(f.vec_from_canonical(&radial), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(f.vec_from_canonical(&normal), Vec3::new(0.0, 0.0, -1.0));
        let f = Frame::AlongAntinormalNadir;
        assert_eq!(f.vec_from_canonical(&along), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(f.vec_from_canonical(&normal), Vec3::new(0.0, -1.0, 0.0));
        assert_eq!(f.vec_from_canonical(&radial), Vec3::new(0.0, 0.0, -1.0));
    }

    /// Each paper's equations of motion, written out by hand in its own frame as
    /// `X' = A X` (no thrust), must equal `T6 A_canonical T6^T`.
    #[test]
    fn papers_equations_of_motion_come_out_of_the_conversion() {
        let w: f64 = 1.1e-3;
        let a_c = CwModel::new(w).continuous_a();
        let with_vel = |acc: [[f64; 6]; 3]| {
            let mut a = Mat6::zeros();
            for i in 0..3 {
                a[(i, i + 3)] = 1.0;
                for j in 0..6 {
                    a[(i + 3, j)] = acc[i][j];
                }
            }
            a
        };
        // paper 002 (canonical): x'' - 2w y' - 3w^2 x = 0, y'' + 2w x' = 0, z'' + w^2 z = 0
        let a002 = with_vel([
            [3.0 * w * w, 0.0, 0.0, 0.0, 2.0 * w, 0.0],
            [0.0, 0.0, 0.0, -2.0 * w, 0.0, 0.0],
            [0.0, 0.0, -w * w, 0.0, 0.0, 0.0],
        ]);
        // paper 000: x'' + 2w y' = 0, y'' - 2w x' - 3w^2 y = 0, z'' + w^2 z = 0
        let a000 = with_vel([
            [0.0, 0.0, 0.0, 0.0, -2.0 * w, 0.0],
            [0.0, 3.0 * w * w, 0.0, 2.0 * w, 0.0, 0.0],
            [0.0, 0.0, -w * w, 0.0, 0.0, 0.0],
        ]);
        // paper 003 (x along, y anti-normal, z nadir): x'' = 2w z', y'' = -w^2 y,
        // z'' = 3w^2 z - 2w x'
        let a003 = with_vel([
            [0.0, 0.0, 0.0, 0.0, 0.0, 2.0 * w],
            [0.0, -w * w, 0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 3.0 * w * w, -2.0 * w, 0.0, 0.0],
        ]);
        for (f, a_paper) in [
            (Frame::RadialAlongNormal, a002),
            (Frame::AlongRadialAntinormal, a000),
            (Frame::AlongAntinormalNadir, a003),
        ] {
            let t = f.rotation6();
            let a_io = t * a_c * t.transpose();
            assert!((a_io - a_paper).norm() < 1e-18, "{f:?}\n{a_io}\n{a_paper}");
        }
    }
}
