//! Assembly: element kernels evaluated in parallel, scattered into global vectors and sparse
//! matrices on the free DOFs.
//!
//! Physics lives in the forms, not here (scikit-fem: `asm(form, basis)`; fenris: element
//! assemblers over operators). Three kinds of forms:
//! - a *bilinear* form `a(u, v) = Σ_e Σ_q …` as per-element matrices ([`element_matrices`]: the
//!   caller's closure adds the packed upper triangle of the element matrix at each quadrature
//!   point), assembled with [`Assembly::matrix`];
//! - a *linear* form as per-element vectors ([`element_vectors`]), assembled with
//!   [`Assembly::vector`];
//! - a *non-linear* form: a residual `R(u) = Σ_e r_e(u_e)` with its Jacobian `∂R/∂u`, given by an
//!   [`ElementForm`] and assembled by [`Assembly::evaluate`] into the free-DOF residual and the
//!   Jacobian values. Elements whose Jacobian does not depend on `u` (linear materials: most of a
//!   magnetic mesh) say so ([`ElementForm::has_constant_jacobian`]); their Jacobians are summed
//!   once ([`Assembly::prepare`]) and each evaluation adds only the varying ones to that sum.
//!
//! Element matrices are symmetric and stored as their upper triangle packed row by row (pairs
//! `(i, j)`, `i <= j`: (0,0) (0,1) … (0,N−1) (1,1) …), [`packed_len`]`(N)` values; global matrices
//! as the upper triangle on a [`SymmetricPattern`] of the free DOFs. Constrained DOFs (see
//! [`crate::workflow::constraints`]) are dropped from rows and columns: their values act through the
//! residual. Constant DOF couplings outside the element loop (a boundary integral, e.g. the
//! asymptotic open boundary of magnetostatics) are added with [`Assembly::set_couplings`].
//!
//! The element loops run on rayon's pool in chunks of [`MIN_ELEMENTS_PER_TASK`] elements; the
//! scatter into global arrays is sequential in element order, so the arithmetic (and every result
//! bit) is the same whatever the number of threads.

use std::sync::Arc;

use rayon::prelude::*;

use crate::FemError;
use crate::discretisation::basis::{Basis, Element, QuadraturePoint};
use crate::discretisation::dofs::ElementOrder;
use crate::discretisation::element::{ElementTriP1, ElementTriP2, TriangleBasis};
use crate::linalg::pattern::{CONSTRAINED, SymmetricPattern};
use crate::workflow::constraints::Constraints;

/// Elements per parallel task in the element loops.
pub const MIN_ELEMENTS_PER_TASK: usize = 2048;

/// Number of upper-triangle pairs `(i, j)`, `i <= j`, of an element matrix with `n` DOFs.
pub const fn packed_len(n: usize) -> usize {
    n * (n + 1) / 2
}

/// Upper-triangle pairs of the largest element (P2: 6 DOFs, 21 pairs).
pub const MAX_PACKED_LEN: usize = packed_len(6);

/// The full symmetric `N × N` matrix of its packed upper triangle.
#[inline(always)]
pub fn unpack_symmetric<const N: usize>(packed: &[f64]) -> [[f64; N]; N] {
    let mut full = [[0.0; N]; N];
    let mut p = 0;
    for i in 0..N {
        for j in i..N {
            full[i][j] = packed[p];
            full[j][i] = packed[p];
            p += 1;
        }
    }
    full
}

/// `y += Σ_e w_e M_e x_e`: the product with `x` of a symmetric matrix given by its element
/// matrices (packed upper triangles, [`packed_len`]`(N)` values per element as
/// [`element_matrices`] returns them), element by element and without assembling it. Elements
/// whose weight `w_e` is zero are skipped with their cost (e.g. a mass matrix weighted by a
/// conductivity that only the conductors have). The sum runs in element order, so the result does
/// not depend on threads.
pub fn element_matrix_product<const N: usize>(
    element_dofs: &[usize],
    packed: &[f64],
    weight: impl Fn(usize) -> f64,
    x: &[f64],
    y: &mut [f64],
) {
    let len = packed_len(N);
    for (t, (dofs, m)) in element_dofs.chunks_exact(N).zip(packed.chunks_exact(len)).enumerate() {
        let w = weight(t);
        if w.abs() < f64::MIN_POSITIVE {
            continue;
        }
        let local: [f64; N] = std::array::from_fn(|i| x[dofs[i]]);
        let mut out = [0.0; N];
        let mut p = 0;
        for i in 0..N {
            out[i] += m[p] * local[i];
            p += 1;
            for j in i + 1..N {
                out[i] += m[p] * local[j];
                out[j] += m[p] * local[i];
                p += 1;
            }
        }
        for i in 0..N {
            y[dofs[i]] += w * out[i];
        }
    }
}

/// Calls the generic function `f::<Basis, N>(args)` instantiated for the element order `order`
/// (a [`crate::discretisation::dofs::ElementOrder`]): `ElementTriP1, 3` or `ElementTriP2, 6`.
#[macro_export]
macro_rules! by_order {
    ($order:expr, $($f:ident)::+ ( $($arg:expr),* $(,)? )) => {
        match $order {
            $crate::discretisation::dofs::ElementOrder::P1 => {
                $($f)::+::<$crate::discretisation::element::ElementTriP1, 3>($($arg),*)
            }
            $crate::discretisation::dofs::ElementOrder::P2 => {
                $($f)::+::<$crate::discretisation::element::ElementTriP2, 6>($($arg),*)
            }
        }
    };
}

/// A non-linear form: the residual of each element and its Jacobian.
///
/// The form is generic over the Lagrange basis `E` with `N` local DOFs, so one implementation serves
/// every element order (the assembler picks the instance for the basis's order).
pub trait ElementForm: Sync {
    /// The element residual `r_e(u_e)` into `residual` (`N` values) and, when `jacobian` is
    /// given, the packed upper triangle of `∂r_e/∂u_e` ([`packed_len`]`(N)` values). `local` holds
    /// the values of the element's DOFs in local order. For an element with a constant Jacobian
    /// the form may leave `jacobian` untouched.
    fn element<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        local: [f64; N],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    );

    /// True when element `index`'s Jacobian does not depend on the unknowns (a linear material).
    fn has_constant_jacobian(&self, index: usize) -> bool {
        let _ = index;
        false
    }

    /// The constant Jacobian of an element for which [`Self::has_constant_jacobian`] is true.
    fn constant_jacobian<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        jacobian: &mut [f64],
    ) {
        let _ = (element, jacobian);
        unreachable!("constant_jacobian called on a form without constant elements")
    }
}

/// Per-element packed matrices of a bilinear form: `packed_len(N)` values per element.
///
/// `point_kernel(element, q, out)` adds the contribution of quadrature point `q` of `element` to
/// the element's packed upper triangle `out` (e.g. `out[p] += q.weight * (∇φ_i · ∇φ_j)` for the
/// pairs `p = (i, j)`).
pub fn element_matrices<E: TriangleBasis<N>, const N: usize>(
    basis: &Basis,
    point_kernel: impl Fn(usize, &QuadraturePoint<N>, &mut [f64]) + Sync,
) -> Vec<f64> {
    per_element::<E, N>(basis, packed_len(N), point_kernel)
}

/// Per-element vectors of a linear form: `N` values per element, `point_kernel(element, q, out)`
/// adding point `q`'s contribution (e.g. `out[i] += q.weight * f * φ_i`).
pub fn element_vectors<E: TriangleBasis<N>, const N: usize>(
    basis: &Basis,
    point_kernel: impl Fn(usize, &QuadraturePoint<N>, &mut [f64]) + Sync,
) -> Vec<f64> {
    per_element::<E, N>(basis, N, point_kernel)
}

fn per_element<E: TriangleBasis<N>, const N: usize>(
    basis: &Basis,
    width: usize,
    point_kernel: impl Fn(usize, &QuadraturePoint<N>, &mut [f64]) + Sync,
) -> Vec<f64> {
    let mut out = vec![0.0; width * basis.n_elements()];
    out.par_chunks_mut(width).enumerate().with_min_len(MIN_ELEMENTS_PER_TASK).for_each(
        |(t, out)| {
            let geometry = basis.geometry(t);
            for q in basis.rule() {
                point_kernel(t, &basis.point::<E, N>(&geometry, q), out);
            }
        },
    );
    out
}

/// Constant couplings between global DOFs added to every residual (`R_i += m_ij u_j`) and to the
/// Jacobian (`K_ij += m_ij`).
#[derive(Debug, Clone, Default)]
struct Couplings {
    /// `(i, j, m_ij)` over global DOFs, both orders.
    residual: Vec<(usize, usize, f64)>,
    /// `(value position, m_ij)` once per upper pair of free DOFs.
    matrix: Vec<(usize, f64)>,
}

/// A local symmetric matrix over a few global DOFs (e.g. of a boundary edge), to be added as a
/// constant coupling: `values[a][b]` couples `dofs[a]` and `dofs[b]`.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalMatrix {
    /// The global DOFs.
    pub dofs: Vec<usize>,
    /// The full (symmetric) matrix, `dofs.len()` rows of `dofs.len()` values.
    pub values: Vec<Vec<f64>>,
}

/// The assembly of forms on one basis with one set of constraints: the free-DOF sparsity pattern,
/// the element work arrays, the constant part of the Jacobian and the constant couplings.
#[derive(Debug)]
pub struct Assembly {
    basis: Basis,
    constraints: Constraints,
    /// Shared with the Newton solver of this assembly (no copy of the pattern and scatter map).
    pattern: Arc<SymmetricPattern>,
    element_residual: Vec<f64>,
    element_jacobian: Vec<f64>,
    /// Sum of the constant element Jacobians and the couplings (values on the pattern).
    constant_jacobian: Vec<f64>,
    /// Elements whose Jacobian varies (added to the constant sum at every evaluation).
    varying_elements: Vec<usize>,
    couplings: Couplings,
    prepared: bool,
}

impl Assembly {
    /// Sets up the assembly of `basis` under `constraints`: the sparsity pattern of the free DOFs
    /// and the element work arrays. Fails when every DOF is constrained.
    pub fn new(basis: Basis, constraints: Constraints) -> Result<Self, FemError> {
        if constraints.len() != basis.dofs().len() {
            return Err(FemError::field(
                "constraints",
                format!(
                    "{} constrained-DOF entries for a basis with {} DOFs",
                    constraints.len(),
                    basis.dofs().len()
                ),
            ));
        }
        if constraints.n_free() == 0 {
            return Err(FemError::field(
                "constraints",
                "every node is constrained: nothing to solve",
            ));
        }
        let k = basis.dofs().dofs_per_triangle();
        // The free index of each element DOF is needed only to build the pattern: the scatters
        // look it up through the constraints (kept: 8 bytes per element DOF, 4.6 MB at 100 k nodes).
        let element_free_dofs = constraints.free_dofs_of(basis.dofs().element_dofs());
        let pattern = Arc::new(SymmetricPattern::new(constraints.n_free(), k, &element_free_dofs));
        drop(element_free_dofs);
        let n = basis.n_elements();
        Ok(Self {
            element_residual: vec![0.0; k * n],
            element_jacobian: vec![0.0; packed_len(k) * n],
            constant_jacobian: vec![0.0; pattern.nnz()],
            varying_elements: (0..n).collect(),
            couplings: Couplings::default(),
            prepared: false,
            pattern,
            basis,
            constraints,
        })
    }

    /// The basis.
    pub fn basis(&self) -> &Basis {
        &self.basis
    }

    /// The constraints.
    pub fn constraints(&self) -> &Constraints {
        &self.constraints
    }

    /// The sparsity pattern of the free DOFs.
    pub fn pattern(&self) -> &Arc<SymmetricPattern> {
        &self.pattern
    }

    /// Number of free DOFs (unknowns).
    pub fn n_free(&self) -> usize {
        self.constraints.n_free()
    }

    /// True when no element's Jacobian varies (after [`Self::prepare`]): the form is linear.
    pub fn is_linear(&self) -> bool {
        self.prepared && self.varying_elements.is_empty()
    }

    /// The elements whose Jacobian varies with the unknowns (all of them before
    /// [`Self::prepare`]).
    pub fn varying_elements(&self) -> &[usize] {
        &self.varying_elements
    }

    /// Replaces the constant couplings by the local matrices `terms` (global DOFs), in order.
    /// Call [`Self::prepare`] afterwards. Fails when a coupling of two free DOFs is not in the
    /// pattern (the DOFs share no element).
    pub fn set_couplings(&mut self, terms: &[LocalMatrix]) -> Result<(), FemError> {
        let mut couplings = Couplings::default();
        let free = self.constraints.free_index();
        for term in terms {
            let k = term.dofs.len();
            for i in 0..k {
                for j in 0..k {
                    let m = term.values[i][j];
                    couplings.residual.push((term.dofs[i], term.dofs[j], m));
                    let (di, dj) = (free[term.dofs[i]], free[term.dofs[j]]);
                    if di != CONSTRAINED && dj != CONSTRAINED && i <= j {
                        let position = self.pattern.position(di, dj).ok_or_else(|| {
                            FemError::field(
                                "coupling",
                                format!(
                                    "coupled DOFs {} and {} share no element",
                                    term.dofs[i], term.dofs[j]
                                ),
                            )
                        })?;
                        couplings.matrix.push((position, m));
                    }
                }
            }
        }
        self.couplings = couplings;
        self.prepared = false;
        Ok(())
    }

    /// Sums the constant element Jacobians of `form` and the couplings, and lists the elements
    /// whose Jacobian varies. Call it once per form (and again when the form's constant part
    /// changes, e.g. a new material).
    pub fn prepare<F: ElementForm>(&mut self, form: &F) {
        match self.basis.order() {
            ElementOrder::P1 => self.prepare_with::<ElementTriP1, 3, F>(form),
            ElementOrder::P2 => self.prepare_with::<ElementTriP2, 6, F>(form),
        }
    }

    fn prepare_with<E: TriangleBasis<N>, const N: usize, F: ElementForm>(&mut self, form: &F) {
        let basis = &self.basis;
        self.element_jacobian
            .par_chunks_mut(packed_len(N))
            .enumerate()
            .with_min_len(MIN_ELEMENTS_PER_TASK)
            .for_each(|(t, jacobian)| {
                if form.has_constant_jacobian(t) {
                    form.constant_jacobian(&basis.element::<E, N>(t), jacobian);
                } else {
                    jacobian.iter_mut().for_each(|j| *j = 0.0);
                }
            });
        self.pattern.assemble(&self.element_jacobian, &mut self.constant_jacobian);
        for &(position, value) in &self.couplings.matrix {
            self.constant_jacobian[position] += value;
        }
        self.varying_elements =
            (0..basis.n_elements()).filter(|&t| !form.has_constant_jacobian(t)).collect();
        self.prepared = true;
    }

    /// The residual `R(u)` of `form` on the free DOFs (into `residual`, [`Self::n_free`] values)
    /// and, when asked, the Jacobian values on [`Self::pattern`] (into `jacobian`). `u` holds the
    /// value of every DOF (constrained ones at their prescribed values). Call [`Self::prepare`]
    /// with the same form before asking for the Jacobian.
    pub fn evaluate<F: ElementForm>(
        &mut self,
        form: &F,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        assert!(
            self.prepared || jacobian.is_none(),
            "Assembly::prepare must be called before a Jacobian is evaluated"
        );
        match self.basis.order() {
            ElementOrder::P1 => {
                self.evaluate_with::<ElementTriP1, 3, F>(form, u, residual, jacobian)
            }
            ElementOrder::P2 => {
                self.evaluate_with::<ElementTriP2, 6, F>(form, u, residual, jacobian)
            }
        }
    }

    fn evaluate_with<E: TriangleBasis<N>, const N: usize, F: ElementForm>(
        &mut self,
        form: &F,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let want_jacobian = jacobian.is_some();
        element_residuals::<E, N, F>(
            &self.basis,
            form,
            u,
            &mut self.element_residual,
            want_jacobian.then_some(&mut self.element_jacobian[..]),
        );
        scatter::<N>(
            self.basis.dofs().element_dofs(),
            self.constraints.free_index(),
            &self.element_residual,
            residual,
        );
        let free = self.constraints.free_index();
        for &(i, j, value) in &self.couplings.residual {
            let d = free[i];
            if d != CONSTRAINED {
                residual[d] += value * u[j];
            }
        }
        if let Some(values) = jacobian {
            values.copy_from_slice(&self.constant_jacobian);
            self.pattern.add_elements(&self.varying_elements, &self.element_jacobian, values);
        }
    }

    /// The global matrix (values on [`Self::pattern`]) of per-element packed matrices
    /// ([`element_matrices`]) plus the couplings.
    pub fn matrix(&self, element_matrices: &[f64]) -> Vec<f64> {
        let mut values = vec![0.0; self.pattern.nnz()];
        self.pattern.assemble(element_matrices, &mut values);
        for &(position, value) in &self.couplings.matrix {
            values[position] += value;
        }
        values
    }

    /// The free-DOF vector of per-element vectors ([`element_vectors`]), each element's scaled by
    /// `scale(element)`.
    pub fn vector(&self, element_vectors: &[f64], scale: impl Fn(usize) -> f64) -> Vec<f64> {
        let k = self.basis.dofs().dofs_per_triangle();
        let mut out = vec![0.0; self.n_free()];
        for (t, (dofs, values)) in self
            .basis
            .dofs()
            .element_dofs()
            .chunks_exact(k)
            .zip(element_vectors.chunks_exact(k))
            .enumerate()
        {
            let s = scale(t);
            let free = self.constraints.free_index();
            for (&d, &v) in dofs.iter().map(|&g| &free[g]).zip(values) {
                if d != CONSTRAINED {
                    out[d] += s * v;
                }
            }
        }
        out
    }
}

/// All element residuals in parallel into `element_residual` (`N` per element) and, when
/// `element_jacobian` is given, the element Jacobians (`packed_len(N)` per element).
fn element_residuals<E: TriangleBasis<N>, const N: usize, F: ElementForm>(
    basis: &Basis,
    form: &F,
    u: &[f64],
    element_residual: &mut [f64],
    element_jacobian: Option<&mut [f64]>,
) {
    let element_dofs = basis.dofs().element_dofs();
    let kernel = |t: usize, dofs: &[usize], residual: &mut [f64], jacobian: Option<&mut [f64]>| {
        let dofs: &[usize; N] = dofs.try_into().expect("N DOFs per element");
        form.element(&basis.element::<E, N>(t), dofs.map(|d| u[d]), residual, jacobian);
    };
    let inputs = element_dofs.par_chunks(N);
    match element_jacobian {
        Some(jacobian) => element_residual
            .par_chunks_mut(N)
            .zip(jacobian.par_chunks_mut(packed_len(N)))
            .zip(inputs)
            .enumerate()
            .with_min_len(MIN_ELEMENTS_PER_TASK)
            .for_each(|(t, ((res, jac), dofs))| kernel(t, dofs, res, Some(jac))),
        None => element_residual
            .par_chunks_mut(N)
            .zip(inputs)
            .enumerate()
            .with_min_len(MIN_ELEMENTS_PER_TASK)
            .for_each(|(t, (res, dofs))| kernel(t, dofs, res, None)),
    }
}

/// Adds the element residuals (`N` per element) into the free-DOF vector `out` (zeroed first)
/// through the free index (`free_index`) of each element DOF (`element_dofs`, global).
fn scatter<const N: usize>(
    element_dofs: &[usize],
    free_index: &[usize],
    element_residual: &[f64],
    out: &mut [f64],
) {
    out.iter_mut().for_each(|r| *r = 0.0);
    for (dofs, res) in element_dofs.chunks_exact(N).zip(element_residual.chunks_exact(N)) {
        for k in 0..N {
            let d = free_index[dofs[k]];
            if d != CONSTRAINED {
                out[d] += res[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discretisation::basis::Weighting;
    use crate::discretisation::dofs::ElementOrder;
    use crate::discretisation::element::ElementTriP2;
    use crate::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
    use std::sync::Arc;

    /// The element-by-element product equals the product with the assembled matrix (P2 mass
    /// matrix weighted per element, some elements weighted 0), to rounding.
    #[test]
    fn element_matrix_product_matches_the_assembled_matrix() {
        let lines = graded_lines(0.0, 1.0, 4, 1.3);
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        let mesh = Arc::new(rectangle_mesh(&lines, &lines, |_, _| 1, sides).unwrap());
        let basis = Basis::new(mesh, ElementOrder::P2, 4, Weighting::Axisymmetric);
        let packed = element_matrices::<ElementTriP2, 6>(&basis, |_, q, m| {
            let mut p = 0;
            for i in 0..6 {
                for j in i..6 {
                    m[p] += q.weight * q.phi[i] * q.phi[j];
                    p += 1;
                }
            }
        });
        let weight = |t: usize| if t % 3 == 0 { 0.0 } else { 1.0 + t as f64 };
        let n = basis.dofs().len();
        let mut dense = vec![vec![0.0; n]; n];
        let dofs = basis.dofs().element_dofs();
        for (t, element) in dofs.chunks_exact(6).enumerate() {
            let m = unpack_symmetric::<6>(&packed[21 * t..21 * (t + 1)]);
            for i in 0..6 {
                for j in 0..6 {
                    dense[element[i]][element[j]] += weight(t) * m[i][j];
                }
            }
        }
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let mut y = vec![0.0; n];
        element_matrix_product::<6>(dofs, &packed, weight, &x, &mut y);
        for (row, yi) in dense.iter().zip(&y) {
            let exact: f64 = row.iter().zip(&x).map(|(a, b)| a * b).sum();
            assert!((exact - yi).abs() <= 1e-14 * (1.0 + exact.abs()), "{exact} vs {yi}");
        }
    }
}
