//! The LMIs of the designs as a semidefinite program in Clarabel's PSD cone: symmetric
//! affine matrix functions on a block structure ([`Lmi`]) of scalar variables grouped into
//! matrices ([`VarMat`], [`Vars`]), their assembly and solve ([`Sdp`]), and the linear
//! algebra of the elimination and of the checks (kernel bases, thin factors, the
//! one-row reconstruction, the largest eigenvalue).

use super::{DesignOptions, HinfError};
use crate::hinf::HinfErrorKind;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::DMatrix;

/// A symmetric affine matrix function `M(x) = M0 + sum x_i M_i` on a block structure.
pub(super) struct Lmi {
    dim: usize,
    offsets: Vec<usize>,
    /// `mats[0]` = constant, `mats[i + 1]` = coefficient of variable `i`
    mats: Vec<DMatrix<f64>>,
}

impl Lmi {
    pub(super) fn new(blocks: &[usize], nvar: usize) -> Self {
        let mut offsets = Vec::with_capacity(blocks.len());
        let mut o = 0;
        for b in blocks {
            offsets.push(o);
            o += b;
        }
        Self {
            dim: o,
            offsets,
            mats: vec![DMatrix::zeros(o, o); nvar + 1],
        }
    }

    /// `N^T M(x) N` for every coefficient: the LMI restricted to the range of `N` (one
    /// block of size `N.ncols()` afterwards).
    pub(super) fn congruence(&self, n: &DMatrix<f64>) -> Self {
        Self {
            dim: n.ncols(),
            offsets: vec![0],
            mats: self.mats.iter().map(|m| n.transpose() * m * n).collect(),
        }
    }

    /// Add `m` at block `(r, c)` (and `m^T` at `(c, r)`) to the coefficient of `var`
    /// (`None`: the constant).
    pub(super) fn add(&mut self, var: Option<usize>, r: usize, c: usize, m: &DMatrix<f64>) {
        let k = var.map_or(0, |v| v + 1);
        let (r0, c0) = (self.offsets[r], self.offsets[c]);
        let t = &mut self.mats[k];
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                let v = m[(i, j)];
                if v != 0.0 {
                    t[(r0 + i, c0 + j)] += v;
                    if r != c {
                        t[(c0 + j, r0 + i)] += v;
                    }
                }
            }
        }
    }
}

/// The bound `X <= rho I` on a symmetric certificate `X` (n x n), as the LMI
/// `X - rho I <= 0` (why the certificate is bounded: see the [design docs](super)).
pub(super) fn upper_bound(x: &VarMat, n: usize, nvar: usize, rho: f64) -> Lmi {
    let mut lmi = Lmi::new(&[n], nvar);
    for (k, e) in x.basis() {
        lmi.add(Some(k), 0, 0, &e);
    }
    lmi.add(None, 0, 0, &(-DMatrix::<f64>::identity(n, n) * rho));
    lmi
}

/// A group of scalar variables forming a matrix: symmetric (upper triangle) or full.
#[derive(Clone)]
pub(super) struct VarMat {
    first: usize,
    rows: usize,
    cols: usize,
    sym: bool,
}

impl VarMat {
    fn count(&self) -> usize {
        if self.sym {
            self.rows * (self.rows + 1) / 2
        } else {
            self.rows * self.cols
        }
    }
    /// `(variable index, basis matrix)` for every scalar of the group.
    pub(super) fn basis(&self) -> Vec<(usize, DMatrix<f64>)> {
        let mut out = Vec::with_capacity(self.count());
        let mut k = self.first;
        if self.sym {
            for j in 0..self.rows {
                for i in 0..=j {
                    let mut e = DMatrix::zeros(self.rows, self.rows);
                    e[(i, j)] = 1.0;
                    e[(j, i)] = 1.0;
                    out.push((k, e));
                    k += 1;
                }
            }
        } else {
            for j in 0..self.cols {
                for i in 0..self.rows {
                    let mut e = DMatrix::zeros(self.rows, self.cols);
                    e[(i, j)] = 1.0;
                    out.push((k, e));
                    k += 1;
                }
            }
        }
        out
    }
    pub(super) fn value(&self, x: &[f64]) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(self.rows, self.cols);
        for (k, e) in self.basis() {
            m += e * x[k];
        }
        m
    }
}

pub(super) struct Vars {
    pub(super) n: usize,
}

impl Vars {
    pub(super) fn sym(&mut self, n: usize) -> VarMat {
        let v = VarMat {
            first: self.n,
            rows: n,
            cols: n,
            sym: true,
        };
        self.n += v.count();
        v
    }
    pub(super) fn full(&mut self, r: usize, c: usize) -> VarMat {
        let v = VarMat {
            first: self.n,
            rows: r,
            cols: c,
            sym: false,
        };
        self.n += v.count();
        v
    }
    pub(super) fn scalar(&mut self) -> usize {
        self.n += 1;
        self.n - 1
    }
}

pub(super) fn dm<const R: usize, const C: usize>(m: &nalgebra::SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_fn(R, C, |i, j| m[(i, j)])
}

/// svec of a symmetric matrix in Clarabel's convention: upper triangle by columns,
/// off-diagonal entries times sqrt(2).
fn svec(m: &DMatrix<f64>, out: &mut Vec<f64>) {
    let s2 = core::f64::consts::SQRT_2;
    for j in 0..m.ncols() {
        for i in 0..=j {
            out.push(if i == j { m[(i, j)] } else { s2 * m[(i, j)] });
        }
    }
}

/// The SDP: minimise `c^T x` subject to `-M_k(x) - eps_k I` PSD for every `M_k`, and
/// `x_i >= lo_i` for the listed scalars.
pub(super) struct Sdp {
    pub(super) nvar: usize,
    pub(super) cost: Vec<f64>,
    pub(super) lmis: Vec<(Lmi, f64)>,
    pub(super) lower: Vec<(usize, f64)>,
    /// Let Clarabel equilibrate (Ruiz-scale) the data. Off for the paper design, which is
    /// posed balanced already ([design docs](super), conditioning 1): there Clarabel's
    /// scaling of the 45 x 45 LMI's rows only costs iterations (the same gamma). On for the observer designs, whose quiet-truth cases span many orders of
    /// magnitude and need it (without it the quiet case's gamma-optimal observer ends 1e-3
    /// relative away in gamma).
    pub(super) equilibrate: bool,
}

pub(super) struct SdpSolution {
    pub(super) x: Vec<f64>,
    pub(super) status: SolverStatus,
    pub(super) iterations: u32,
}

impl Sdp {
    pub(super) fn solve(&self, opts: &DesignOptions) -> Result<SdpSolution, HinfError> {
        // columns as triplets
        let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
        let mut b = Vec::new();
        let mut cones = Vec::new();
        let mut row0 = 0;
        let mut buf = Vec::new();
        for (lmi, eps) in &self.lmis {
            let mut m0 = -&lmi.mats[0];
            for i in 0..lmi.dim {
                m0[(i, i)] -= eps;
            }
            svec(&m0, &mut b);
            for (k, mk) in lmi.mats[1..].iter().enumerate() {
                buf.clear();
                svec(mk, &mut buf);
                for (r, v) in buf.iter().enumerate() {
                    if *v != 0.0 {
                        rows.push(row0 + r);
                        cols.push(k);
                        vals.push(*v);
                    }
                }
            }
            row0 += lmi.dim * (lmi.dim + 1) / 2;
            cones.push(SupportedConeT::PSDTriangleConeT(lmi.dim));
        }
        // x_i - lo >= 0  <=>  s = -lo - (-1) x_i
        for (i, lo) in &self.lower {
            rows.push(row0);
            cols.push(*i);
            vals.push(-1.0);
            b.push(-lo);
            row0 += 1;
        }
        if !self.lower.is_empty() {
            cones.push(SupportedConeT::NonnegativeConeT(self.lower.len()));
        }
        let a = CscMatrix::new_from_triplets(row0, self.nvar, rows, cols, vals);
        let p = CscMatrix::zeros((self.nvar, self.nvar));
        let settings = DefaultSettings {
            max_iter: opts.max_iter,
            verbose: false,
            // Clarabel's own choice of LDL per KKT matrix (its `faer-sparse` feature, as in
            // its Python wheel): faer's supernodal factorisation where the KKT system is
            // dense enough (flops / nnz(L) >= 40: the literal paper form's PSD blocks, where
            // it halves the solve's work), QDLDL elsewhere (the eliminated paper form, the
            // observer designs)
            // one thread: deterministic, and the machine's cores belong to the caller
            max_threads: 1,
            equilibrate_enable: self.equilibrate,
            direct_solve_method: "auto".to_string(),
            ..DefaultSettings::default()
        };
        let mut solver =
            DefaultSolver::new(&p, &self.cost, &a, &b, &cones, settings).map_err(|e| {
                HinfError {
                    kind: HinfErrorKind::SolverFailed,
                    message: format!("Clarabel rejected the problem: {e:?}").into(),
                }
            })?;
        crate::numerics::blas::single_thread();
        solver.solve();
        let status = solver.solution.status;
        match status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(SdpSolution {
                x: solver.solution.x.clone(),
                status,
                iterations: solver.solution.iterations,
            }),
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                Err(HinfError {
                    kind: HinfErrorKind::Infeasible,
                    message: format!(
                        "no filter satisfies the LMI (Clarabel: {status:?} after {} \
                         iterations)",
                        solver.solution.iterations
                    )
                    .into(),
                })
            }
            other => Err(HinfError {
                kind: HinfErrorKind::SolverFailed,
                message: format!(
                    "Clarabel stopped with {other:?} after {} iterations",
                    solver.solution.iterations
                )
                .into(),
            }),
        }
    }
}

pub(super) fn status_name(s: SolverStatus) -> &'static str {
    match s {
        SolverStatus::Solved => "Solved",
        SolverStatus::AlmostSolved => "AlmostSolved",
        _ => "Other",
    }
}

/// Largest eigenvalue of a symmetric matrix (NaN when it is not finite or the capped
/// eigensolver does not converge: every caller's `< 0` test then fails).
pub(crate) fn max_eig(m: &DMatrix<f64>) -> f64 {
    let sym = (m + m.transpose()) * 0.5;
    match crate::numerics::eigen::symmetric_eigenvalues(sym) {
        Some(ev) => ev.iter().fold(f64::NEG_INFINITY, |a, b| a.max(*b)),
        None => f64::NAN,
    }
}

/// `N = diag(I_6, [I_6; -D^-1 C], I_rest)`: the basis of `{(row, x, v, rest) : C x + D v =
/// 0}` for an LMI with blocks `(row 6, x 6, v m, rest)`, `m` the rows of `C`.
pub(super) fn kernel_basis(dinv_c: &DMatrix<f64>, rest: usize) -> DMatrix<f64> {
    let m = dinv_c.nrows();
    let mut kern = DMatrix::zeros(12 + m + rest, 12 + rest);
    for i in 0..12 {
        kern[(i, i)] = 1.0;
    }
    for i in 0..m {
        for j in 0..6 {
            kern[(12 + i, 6 + j)] = -dinv_c[(i, j)];
        }
    }
    for i in 0..rest {
        kern[(12 + m + i, 12 + i)] = 1.0;
    }
    kern
}

/// A thin factor `F` (n x r) with `F F^T = M M^T` to working precision, `r` the numerical
/// rank of `M` (eigenvalues of `M M^T` above `1e-24` of the largest are kept): an input
/// that enters an LMI only as `X M` beside a block `-c I` can be replaced by `F` ([design
/// docs](super)). `M` itself when the eigensolver fails (exact, just not smaller).
pub(super) fn thin_factor(m: &DMatrix<f64>) -> DMatrix<f64> {
    let Some(eig) = crate::numerics::eigen::symmetric_eigen(m * m.transpose()) else {
        return m.clone();
    };
    let top = eig.eigenvalues.iter().fold(0.0_f64, |a, b| a.max(*b));
    let keep: Vec<usize> = (0..eig.eigenvalues.len())
        .filter(|&i| eig.eigenvalues[i] > top * 1e-24)
        .collect();
    if keep.is_empty() {
        // M = 0: one zero column keeps the block structure
        return DMatrix::zeros(m.nrows(), 1);
    }
    let mut f = DMatrix::zeros(m.nrows(), keep.len());
    for (c, &i) in keep.iter().enumerate() {
        let sd = eig.eigenvalues[i].sqrt();
        for row in 0..m.nrows() {
            f[(row, c)] = eig.eigenvectors[(row, i)] * sd;
        }
    }
    f
}

/// `Theta = -Psi_jr Q^-1 V_r^T (V_r Q^-1 V_r^T)^-1`, `Q = -Psi_rr`: a solution of `Psi +
/// E_j^T Theta V + V^T Theta^T E_j < 0` when the variable enters one block row `j` only
/// (`V` zero in those columns), `Psi_rr < 0` and `Psi` is negative on `ker V` ([design
/// docs](super), "Reconstruction"). `None` when `Q` is not positive definite or `V_r Q^-1 V_r^T`
/// is singular.
pub(super) fn one_row_solution(
    psi: &DMatrix<f64>,
    rows: core::ops::Range<usize>,
    v: &DMatrix<f64>,
) -> Option<DMatrix<f64>> {
    let rest: Vec<usize> = (0..psi.nrows()).filter(|i| !rows.contains(i)).collect();
    let row: Vec<usize> = rows.collect();
    let q = -psi.select_rows(&rest).select_columns(&rest);
    let chol = q.cholesky()?;
    let vr = v.select_columns(&rest);
    let qi_vt = chol.solve(&vr.transpose());
    let gram = (&vr * &qi_vt).cholesky()?;
    let psi_jr = psi.select_rows(&row).select_columns(&rest);
    Some(-(psi_jr * gram.solve(&qi_vt.transpose()).transpose()))
}
