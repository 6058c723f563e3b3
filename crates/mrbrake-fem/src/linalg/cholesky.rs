//! Sparse Cholesky factorisation (faer) with the symbolic analysis done once per pattern.
//!
//! The symbolic step (fill-reducing ordering, elimination tree, supernode partition) depends only
//! on the [`SymmetricPattern`]; the ordering is faer's AMD or one given by the caller (e.g. the
//! geometric nested dissection of [`crate::linalg::ordering`]); it is computed in [`SparseCholesky::new`]
//! and shared by every later numeric factorisation: all Newton iterations and all solves on the
//! same mesh. The numeric factor and its workspace are allocated once and overwritten.
//!
//! Two things are done here rather than left to faer, because a Newton solve repeats them many
//! times on the same pattern (measured on the 95 k-unknown saturating benchmark with `perf`):
//! - *the symmetric permutation of the matrix*: faer permutes (and transposes) the input matrix
//!   on every numeric factorisation (`permute_self_adjoint_to_unsorted`, a counting sort of all
//!   entries). Here the permuted lower-triangle structure is built once, with the position of
//!   every input entry in it, so each factorisation only scatters the values (one pass) and faer
//!   factorises with the identity order;
//! - *the triangular solves with one right-hand side*: faer's supernodal solve calls its general
//!   dense kernels (triangular solve, matrix–vector product, temporary allocation) per supernode,
//!   which costs more than the arithmetic for the many small supernodes of a 2D mesh. The solve
//!   here walks the same supernodal factor column by column (`L y = b` by columns with one
//!   gathered update vector per supernode, `Lᵀ x = y` by dot products), which is the textbook
//!   supernodal forward/backward substitution (Davis, *Direct Methods for Sparse Linear Systems*,
//!   SIAM 2006, §4.7 and §9.1) and is bound by reading `L` once per direction. Below the chain
//!   of supernodes at the top of the elimination tree the tree splits into independent subtrees
//!   (with nested dissection: the two halves of the first separator), which are solved in
//!   parallel (see `SubtreePlan`).

use std::ops::Range;
use std::sync::Arc;

use rayon::prelude::*;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

use super::failure::faer_words;
use crate::FemError;
use crate::linalg::pattern::SymmetricPattern;

/// Reusable sparse `L Lᵀ` factorisation for matrices sharing one symmetric pattern.
pub struct SparseCholesky {
    /// Lower triangle of the permuted matrix `P A Pᵀ` (compressed columns, sorted rows).
    structure: SymbolicSparseColMat<usize>,
    symbolic: Arc<SymbolicCholesky<usize>>,
    /// `order[k]` = the original row eliminated k-th.
    order: Vec<usize>,
    /// Position in `permuted_values` of every entry of the caller's upper-triangle pattern.
    value_map: Vec<usize>,
    permuted_values: Vec<f64>,
    l_values: Vec<f64>,
    /// `L` rounded to single precision for [`Self::precondition_in_place`], made on first use
    /// after each factorisation (empty when stale).
    l_values_single: Vec<f32>,
    factor_workspace: MemBuffer,
    solve_workspace: MemBuffer,
    /// Right-hand side in elimination order, and the per-supernode update vector.
    permuted_rhs: Vec<f64>,
    update: Vec<f64>,
    /// Independent subtrees for parallel triangular solves (`None`: the tree does not split).
    subtree_plan: Option<SubtreePlan>,
    factorised: bool,
    parallelism: Par,
    /// Solve with faer's own triangular solves instead of the supernodal walk below (the fallback
    /// should a faer release change the supernodal layout this module reads).
    faer_solve: bool,
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseCholesky")
            .field("n", &self.structure.nrows())
            .field("factor_nnz", &self.l_values.len())
            .field("factorised", &self.factorised)
            .finish_non_exhaustive()
    }
}

impl SparseCholesky {
    /// Symbolic analysis of `pattern` (upper triangle) with the AMD ordering. `threads` is the
    /// parallelism of faer's numeric factorisation (its dense kernels inside supernodes; `0`:
    /// rayon's global pool, `1`: sequential). The triangular solves of [`Self::solve_in_place`]
    /// run the independent subtrees below the top separator on rayon's pool whenever it has more
    /// than one thread.
    pub fn new(pattern: &SymmetricPattern, threads: usize) -> Result<Self, FemError> {
        Self::with_order(pattern, threads, None)
    }

    /// Symbolic analysis with the elimination order `order` (`order[k]` = the row eliminated k-th,
    /// a permutation of `0..n`), or AMD when `None`. A list that is not a permutation is an error.
    pub fn with_order(
        pattern: &SymmetricPattern,
        threads: usize,
        order: Option<&[usize]>,
    ) -> Result<Self, FemError> {
        let n = pattern.n;
        let out_of_memory =
            |_| FemError::Numerical("out of memory for the Cholesky workspace".into());
        let order = match order {
            Some(order) => order.to_vec(),
            None => amd_order(pattern)?,
        };
        let inverse = inverse_permutation(&order, n)?;
        let (structure, value_map) = permuted_lower_structure(pattern, &inverse);
        // With the identity order faer's symbolic analysis reads the upper triangle (the numeric
        // supernodal factorisation the lower one).
        let symbolic = factorize_symbolic_cholesky(
            transpose(&structure).as_ref(),
            Side::Upper,
            SymmetricOrdering::Identity,
            symbolic_params(n),
        )
        .map_err(|e| {
            FemError::Numerical(format!("symbolic Cholesky analysis failed: {}", faer_words(&e)))
        })?;
        let parallelism = if threads == 1 { Par::Seq } else { Par::rayon(threads) };
        let factor_req =
            symbolic.factorize_numeric_llt_scratch::<f64>(parallelism, Default::default());
        let solve_req = symbolic.solve_in_place_scratch::<f64>(1, parallelism);
        let max_update = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                s.col_ptr_for_row_idx().windows(2).map(|w| w[1] - w[0]).max().unwrap_or(0)
            }
            SymbolicCholeskyRaw::Simplicial(_) => 0,
        };
        let subtree_plan = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => SubtreePlan::new(
                &Supernodes {
                    begin: s.supernode_begin(),
                    end: s.supernode_end(),
                    row_ptr: s.col_ptr_for_row_idx(),
                    value_ptr: s.col_ptr_for_val(),
                    row_idx: s.row_idx(),
                },
                n,
                max_update,
            ),
            _ => None,
        };
        Ok(Self {
            subtree_plan,
            l_values: vec![0.0; symbolic.len_val()],
            l_values_single: Vec::new(),
            permuted_values: vec![0.0; structure.compute_nnz()],
            structure,
            symbolic: Arc::new(symbolic),
            order,
            value_map,
            factor_workspace: MemBuffer::try_new(factor_req).map_err(out_of_memory)?,
            solve_workspace: MemBuffer::try_new(solve_req).map_err(out_of_memory)?,
            permuted_rhs: vec![0.0; n],
            update: vec![0.0; max_update],
            factorised: false,
            parallelism,
            faer_solve: false,
        })
    }

    /// Uses faer's own triangular solves (`true`) or the supernodal substitution of this module
    /// (`false`, the default: faster for the many small supernodes of 2D meshes). The module reads
    /// faer's supernodal storage, so the workspace pins faer's exact version; this switch is the
    /// fallback if a faer update changes that storage, and a test checks both agree.
    pub fn set_faer_solve(&mut self, faer_solve: bool) {
        self.faer_solve = faer_solve;
    }

    /// True when a numeric factorisation succeeded (solves are possible).
    pub fn is_factorised(&self) -> bool {
        self.factorised
    }

    /// Number of stored values in the factor `L` (a measure of fill-in).
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    /// Numeric factorisation of the matrix with upper-triangle `values` (pattern order). Fails with
    /// [`FemError::NotPositiveDefinite`] (naming the row of the failing pivot) when the matrix is not
    /// numerically positive definite.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), FemError> {
        self.factorised = false;
        self.l_values_single.clear();
        if values.len() != self.value_map.len() {
            return Err(FemError::Numerical(format!(
                "{} matrix values given, the pattern has {}",
                values.len(),
                self.value_map.len()
            )));
        }
        for (&position, &value) in self.value_map.iter().zip(values) {
            self.permuted_values[position] = value;
        }
        let matrix = SparseColMatRef::new(self.structure.as_ref(), &self.permuted_values);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                matrix,
                Side::Lower,
                Default::default(),
                self.parallelism,
                MemStack::new(&mut self.factor_workspace),
                Default::default(),
            )
            .map_err(|LltError::NonPositivePivot { index }| FemError::NotPositiveDefinite {
                row: self.order.get(index).copied().unwrap_or(index),
                rows: self.order.len(),
            })?;
        self.factorised = true;
        Ok(())
    }

    /// Solves `A x = rhs` in place with the last factorisation.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), FemError> {
        self.substitute(rhs, false)
    }

    /// Applies `M⁻¹` in place, where `M = L̃ L̃ᵀ` and `L̃` is the last Cholesky factor rounded to
    /// single precision (arithmetic stays in double precision). `M` is symmetric positive
    /// definite whatever the rounding, and the triangular solves read half the bytes of
    /// [`Self::solve_in_place`] (they are bound by reading `L`), so this is the cheaper choice
    /// for a preconditioner applied several times per factorisation. The rounded copy is made on
    /// the first call after a factorisation (one pass over `L`). Falls back to the exact solve
    /// for simplicial (small) factors.
    pub fn precondition_in_place(&mut self, rhs: &mut [f64]) -> Result<(), FemError> {
        self.substitute(rhs, true)
    }

    fn substitute(&mut self, rhs: &mut [f64], single: bool) -> Result<(), FemError> {
        if !self.factorised {
            return Err(FemError::Numerical(
                "solve requested before a successful factorisation".into(),
            ));
        }
        if rhs.len() != self.structure.nrows() {
            return Err(FemError::Numerical(format!(
                "right-hand side has {} entries, the matrix {} rows",
                rhs.len(),
                self.structure.nrows()
            )));
        }
        let mut x = std::mem::take(&mut self.permuted_rhs);
        for (xk, &original) in x.iter_mut().zip(&self.order) {
            *xk = rhs[original];
        }
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(symbolic) if !self.faer_solve => {
                let supernodes = Supernodes {
                    begin: symbolic.supernode_begin(),
                    end: symbolic.supernode_end(),
                    row_ptr: symbolic.col_ptr_for_row_idx(),
                    value_ptr: symbolic.col_ptr_for_val(),
                    row_idx: symbolic.row_idx(),
                };
                // Subtrees in parallel only when rayon has a second thread to run them on.
                let plan = self.subtree_plan.as_mut().filter(|_| rayon::current_num_threads() > 1);
                if single {
                    if self.l_values_single.is_empty() {
                        self.l_values_single.extend(self.l_values.iter().map(|&v| v as f32));
                    }
                    supernodes.solve(&self.l_values_single, &mut x, &mut self.update, plan);
                } else {
                    supernodes.solve(&self.l_values, &mut x, &mut self.update, plan);
                }
            }
            _ => {
                // Small or very sparse factors (simplicial), or the fallback: faer's own solve
                // (identity order here).
                let n = x.len();
                let llt =
                    faer::sparse::linalg::cholesky::LltRef::new(&self.symbolic, &self.l_values);
                llt.solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(&mut x, n, 1),
                    self.parallelism,
                    MemStack::new(&mut self.solve_workspace),
                );
            }
        }
        for (xk, &original) in x.iter().zip(&self.order) {
            rhs[original] = *xk;
        }
        self.permuted_rhs = x;
        Ok(())
    }
}

/// Below this order faer's own choice between the simplicial and the supernodal factor stands.
const FORCE_SUPERNODAL_FROM: usize = 2000;

/// The symbolic parameters: from [`FORCE_SUPERNODAL_FROM`] unknowns on, always the supernodal
/// factor. faer's heuristic (flops per factor entry) picks the simplicial factor for the sparse
/// factors of mid-sized 2D meshes, whose triangular solves then run in faer's generic column
/// loop; a time-stepping solve reuses one factor for hundreds of solves, where the supernodal
/// substitution of this module is the faster one (measured with `perf` on the 16 k-node linear
/// transient of `mrbrake-magnetics`' dynamics benchmark: faer's simplicial solves took 44 % of the
/// run; the supernodal walk cut the run by 15–20 %).
fn symbolic_params(n: usize) -> CholeskySymbolicParams<'static> {
    let mut params = CholeskySymbolicParams::default();
    if n >= FORCE_SUPERNODAL_FROM {
        params.supernodal_flop_ratio_threshold = SupernodalThreshold::FORCE_SUPERNODAL;
    }
    params
}

/// The supernode partition of a supernodal factor: supernode `s` holds columns
/// `begin[s]..end[s]`, stored column-major as a dense `(ncols + pattern) × ncols` block at
/// `value_ptr[s]..value_ptr[s + 1]` (diagonal block on top), where the rows below the diagonal
/// block are `row_idx[row_ptr[s]..row_ptr[s + 1]]`.
struct Supernodes<'a> {
    begin: &'a [usize],
    end: &'a [usize],
    row_ptr: &'a [usize],
    value_ptr: &'a [usize],
    row_idx: &'a [usize],
}

impl Supernodes<'_> {
    /// `x ← L⁻¹ x` over the supernodes `range` (in elimination order), whose columns are
    /// `col0..col0 + x_own.len()`; rows at or beyond `top_start` (ancestors outside the range) are
    /// updated in `top` (indexed from `top_start`) instead.
    #[allow(clippy::too_many_arguments)]
    fn forward<T: Copy + Into<f64>>(
        &self,
        l_values: &[T],
        range: Range<usize>,
        col0: usize,
        x_own: &mut [f64],
        top_start: usize,
        top: &mut [f64],
        update: &mut [f64],
    ) {
        for s in range {
            let (first, ncols) = (self.begin[s] - col0, self.end[s] - self.begin[s]);
            let rows = &self.row_idx[self.row_ptr[s]..self.row_ptr[s + 1]];
            let nrows = ncols + rows.len();
            let block = &l_values[self.value_ptr[s]..self.value_ptr[s + 1]];
            let update = &mut update[..rows.len()];
            update.iter_mut().for_each(|u| *u = 0.0);
            let x_top = &mut x_own[first..first + ncols];
            for (j, column) in block.chunks_exact(nrows).enumerate() {
                let xj = x_top[j] / column[j].into();
                x_top[j] = xj;
                for (xi, &l) in x_top[j + 1..].iter_mut().zip(&column[j + 1..ncols]) {
                    *xi -= l.into() * xj;
                }
                for (u, &l) in update.iter_mut().zip(&column[ncols..]) {
                    *u += l.into() * xj;
                }
            }
            for (&row, u) in rows.iter().zip(update.iter()) {
                if row >= top_start {
                    top[row - top_start] -= u;
                } else {
                    x_own[row - col0] -= u;
                }
            }
        }
    }

    /// `x ← L⁻ᵀ x` over the supernodes `range` in reverse elimination order (columns as in
    /// [`Self::forward`]); rows at or beyond `top_start` are read from `top`.
    #[allow(clippy::too_many_arguments)]
    fn backward<T: Copy + Into<f64>>(
        &self,
        l_values: &[T],
        range: Range<usize>,
        col0: usize,
        x_own: &mut [f64],
        top_start: usize,
        top: &[f64],
        update: &mut [f64],
    ) {
        for s in range.rev() {
            let (first, ncols) = (self.begin[s] - col0, self.end[s] - self.begin[s]);
            let rows = &self.row_idx[self.row_ptr[s]..self.row_ptr[s + 1]];
            let nrows = ncols + rows.len();
            let block = &l_values[self.value_ptr[s]..self.value_ptr[s + 1]];
            let update = &mut update[..rows.len()];
            for (u, &row) in update.iter_mut().zip(rows) {
                *u = if row >= top_start { top[row - top_start] } else { x_own[row - col0] };
            }
            let x_top = &mut x_own[first..first + ncols];
            for j in (0..ncols).rev() {
                let column = &block[j * nrows..(j + 1) * nrows];
                let below =
                    dot(&column[ncols..], update) + dot(&column[j + 1..ncols], &x_top[j + 1..]);
                x_top[j] = (x_top[j] - below) / column[j].into();
            }
        }
    }

    /// `x ← (L Lᵀ)⁻¹ x`: sequentially, or with the independent subtrees of `plan` in parallel.
    fn solve<T: Copy + Into<f64> + Sync>(
        &self,
        l_values: &[T],
        x: &mut [f64],
        update: &mut [f64],
        plan: Option<&mut SubtreePlan>,
    ) {
        let n = x.len();
        let Some(plan) = plan else {
            self.forward(l_values, 0..self.begin.len(), 0, x, n, &mut [], update);
            self.backward(l_values, 0..self.begin.len(), 0, x, n, &[], update);
            return;
        };
        let top_start = plan.top_start;
        // Forward: subtrees in parallel, each with a private copy of its updates to the top rows.
        {
            let (mut own, _) = x.split_at_mut(top_start);
            let mut jobs = Vec::with_capacity(plan.tasks.len());
            for (task, buffers) in plan.tasks.iter().zip(plan.buffers.iter_mut()) {
                let (mine, rest) = own.split_at_mut(task.columns.end - task.columns.start);
                own = rest;
                jobs.push((task, mine, buffers));
            }
            jobs.par_iter_mut().for_each(|(task, mine, buffers)| {
                let SubtreeBuffers { top, update } = buffers;
                top.iter_mut().for_each(|t| *t = 0.0);
                self.forward(
                    l_values,
                    task.supernodes.clone(),
                    task.columns.start,
                    mine,
                    top_start,
                    top,
                    update,
                );
            });
        }
        for buffers in &plan.buffers {
            for (xi, t) in x[top_start..].iter_mut().zip(&buffers.top) {
                *xi += t;
            }
        }
        let chain = plan.chain.clone();
        self.forward(l_values, chain.clone(), top_start, &mut x[top_start..], n, &mut [], update);
        // Backward: the top first, then the subtrees in parallel (they only read the top rows).
        self.backward(l_values, chain, top_start, &mut x[top_start..], n, &[], update);
        let (mut own, top) = x.split_at_mut(top_start);
        let top: &[f64] = top;
        let mut jobs = Vec::with_capacity(plan.tasks.len());
        for (task, buffers) in plan.tasks.iter().zip(plan.buffers.iter_mut()) {
            let (mine, rest) = own.split_at_mut(task.columns.end - task.columns.start);
            own = rest;
            jobs.push((task, mine, &mut buffers.update));
        }
        jobs.par_iter_mut().for_each(|(task, mine, update)| {
            self.backward(
                l_values,
                task.supernodes.clone(),
                task.columns.start,
                mine,
                top_start,
                top,
                update,
            );
        });
    }
}

/// One independent subtree of the supernodal elimination tree: its supernodes and columns (both
/// contiguous in a postorder).
#[derive(Debug, Clone)]
struct Subtree {
    supernodes: Range<usize>,
    columns: Range<usize>,
}

/// Work buffers of one subtree task.
#[derive(Debug, Clone)]
struct SubtreeBuffers {
    top: Vec<f64>,
    update: Vec<f64>,
}

/// Parallel triangular solves: below the chain of supernodes at the top of the elimination tree
/// (each with a single child), the tree splits into independent subtrees (the two halves of the
/// first nested-dissection separator). Their columns never meet except through updates to the
/// top rows, so each subtree is solved by its own thread with a private copy of those updates
/// (summed before the top is solved), and the backward solve does the top first, then the
/// subtrees, which only read it.
#[derive(Debug, Clone)]
struct SubtreePlan {
    tasks: Vec<Subtree>,
    buffers: Vec<SubtreeBuffers>,
    /// Supernodes of the top chain and its first column.
    chain: Range<usize>,
    top_start: usize,
}

impl SubtreePlan {
    /// The plan for a supernodal factor, or `None` when the tree does not split into at least
    /// two subtrees below its top chain, or the supernodes are not in a postorder.
    fn new(supernodes: &Supernodes<'_>, n: usize, max_update: usize) -> Option<Self> {
        let count = supernodes.begin.len();
        let mut supernode_of_column = vec![0usize; n];
        for s in 0..count {
            supernode_of_column[supernodes.begin[s]..supernodes.end[s]].fill(s);
        }
        // Parent = the supernode holding the first row below the diagonal block; `count` marks
        // a root (children of a virtual root).
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); count + 1];
        for s in 0..count {
            let rows = &supernodes.row_idx[supernodes.row_ptr[s]..supernodes.row_ptr[s + 1]];
            let parent = rows.iter().min().map_or(count, |&r| supernode_of_column[r]);
            if parent != count && parent <= s {
                return None; // not a postorder
            }
            children[parent].push(s);
        }
        let mut top = count;
        while children[top].len() == 1 {
            top = children[top][0];
        }
        if children[top].len() < 2 {
            return None;
        }
        // First descendant of every supernode (its subtree is `first..=s` in a postorder).
        let mut first = (0..count).collect::<Vec<_>>();
        let mut size = vec![1usize; count];
        for s in 0..count {
            for &c in &children[s] {
                first[s] = first[s].min(first[c]);
                size[s] += size[c];
            }
        }
        let mut tasks = Vec::new();
        let mut next = 0;
        for &c in &children[top] {
            if first[c] != next || size[c] != c + 1 - first[c] {
                return None;
            }
            tasks.push(Subtree {
                supernodes: first[c]..c + 1,
                columns: supernodes.begin[first[c]]..supernodes.end[c],
            });
            next = c + 1;
        }
        let chain_first = if top == count { count } else { next };
        let top_start = if top == count { n } else { supernodes.begin[chain_first] };
        if tasks.last().map(|t| t.columns.end) != Some(top_start) {
            return None;
        }
        let buffers = tasks
            .iter()
            .map(|_| SubtreeBuffers {
                top: vec![0.0; n - top_start],
                update: vec![0.0; max_update],
            })
            .collect();
        Some(Self { tasks, buffers, chain: chain_first..count, top_start })
    }
}

/// Dot product with four independent partial sums (vectorisable without re-association).
#[inline]
fn dot<T: Copy + Into<f64>>(a: &[T], b: &[f64]) -> f64 {
    let mut partial = [0.0; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (a_rest, b_rest) = (a4.remainder(), b4.remainder());
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            partial[k] += x[k].into() * y[k];
        }
    }
    let mut sum = (partial[0] + partial[1]) + (partial[2] + partial[3]);
    for (&x, y) in a_rest.iter().zip(b_rest) {
        sum += x.into() * y;
    }
    sum
}

/// The transpose of a square pattern (rows sorted in every column).
fn transpose(structure: &SymbolicSparseColMat<usize>) -> SymbolicSparseColMat<usize> {
    let n = structure.ncols();
    let (col_ptr, row_idx) = (structure.col_ptr(), structure.row_idx());
    let mut new_ptr = vec![0usize; n + 1];
    for &i in row_idx {
        new_ptr[i + 1] += 1;
    }
    for i in 0..n {
        new_ptr[i + 1] += new_ptr[i];
    }
    let mut fill = new_ptr.clone();
    let mut new_rows = vec![0usize; row_idx.len()];
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            new_rows[fill[i]] = j;
            fill[i] += 1;
        }
    }
    SymbolicSparseColMat::new_checked(n, n, new_ptr, None, new_rows)
}

/// faer's approximate minimum degree order of the pattern.
fn amd_order(pattern: &SymmetricPattern) -> Result<Vec<usize>, FemError> {
    use faer::sparse::linalg::amd;
    let n = pattern.n;
    let structure = SymbolicSparseColMat::new_checked(
        n,
        n,
        pattern.col_ptr.clone(),
        None,
        pattern.row_idx.clone(),
    );
    let mut forward = vec![0usize; n];
    let mut inverse = vec![0usize; n];
    let mut memory = MemBuffer::try_new(amd::order_scratch::<usize>(n, pattern.nnz()))
        .map_err(|_| FemError::Numerical("out of memory for the AMD ordering".into()))?;
    amd::order(
        &mut forward,
        &mut inverse,
        structure.as_ref(),
        Default::default(),
        MemStack::new(&mut memory),
    )
    .map_err(|e| FemError::Numerical(format!("AMD ordering failed: {}", faer_words(&e))))?;
    Ok(forward)
}

/// Lower triangle of `P A Pᵀ` in compressed columns with sorted rows, where `A` has the upper
/// `pattern` and `inverse[i]` is the new index of row `i`; and the position of every entry of
/// `pattern` in it.
fn permuted_lower_structure(
    pattern: &SymmetricPattern,
    inverse: &[usize],
) -> (SymbolicSparseColMat<usize>, Vec<usize>) {
    let n = pattern.n;
    let nnz = pattern.nnz();
    let new_entry = |p: usize, j: usize| {
        let (a, b) = (inverse[pattern.row_idx[p]], inverse[j]);
        (a.max(b), a.min(b)) // (row, column) in the lower triangle
    };
    let mut col_ptr = vec![0usize; n + 1];
    for j in 0..n {
        for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            col_ptr[new_entry(p, j).1 + 1] += 1;
        }
    }
    for j in 0..n {
        col_ptr[j + 1] += col_ptr[j];
    }
    let mut fill = col_ptr.clone();
    let mut entries = vec![(0usize, 0usize); nnz]; // (new row, original position)
    for j in 0..n {
        for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            let (row, column) = new_entry(p, j);
            entries[fill[column]] = (row, p);
            fill[column] += 1;
        }
    }
    let mut value_map = vec![0usize; nnz];
    let mut row_idx = vec![0usize; nnz];
    for j in 0..n {
        let column = &mut entries[col_ptr[j]..col_ptr[j + 1]];
        column.sort_unstable();
        for (k, &(row, p)) in column.iter().enumerate() {
            row_idx[col_ptr[j] + k] = row;
            value_map[p] = col_ptr[j] + k;
        }
    }
    (SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx), value_map)
}

/// `inverse[order[k]] = k`, checking that `order` is a permutation of `0..n`.
fn inverse_permutation(order: &[usize], n: usize) -> Result<Vec<usize>, FemError> {
    let not_a_permutation =
        || FemError::Numerical(format!("elimination order is not a permutation of 0..{n}"));
    if order.len() != n {
        return Err(not_a_permutation());
    }
    let mut inverse = vec![usize::MAX; n];
    for (k, &v) in order.iter().enumerate() {
        if v >= n || inverse[v] != usize::MAX {
            return Err(not_a_permutation());
        }
        inverse[v] = k;
    }
    Ok(inverse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::pattern::SymmetricPattern;

    #[test]
    fn solves_a_1d_laplacian() {
        // Chain of 2-node "elements" with stiffness [1 -1; -1 1], first node constrained.
        let n = 50;
        let mut dofs = Vec::new();
        dofs.extend([crate::linalg::pattern::CONSTRAINED, 0]);
        for i in 0..n - 1 {
            dofs.extend([i, i + 1]);
        }
        let pattern = SymmetricPattern::new(n, 2, &dofs);
        let element_upper: Vec<f64> = (0..n).flat_map(|_| [1.0, -1.0, 1.0]).collect();
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&element_upper, &mut values);
        let mut chol = SparseCholesky::new(&pattern, 1).unwrap();
        chol.factorize(&values).unwrap();
        let mut rhs = vec![0.0; n];
        rhs[n - 1] = 1.0; // unit end load: x_i = i + 1
        chol.solve_in_place(&mut rhs).unwrap();
        for (i, x) in rhs.iter().enumerate() {
            assert!((x - (i + 1) as f64).abs() < 1e-10);
        }
        // Reuse: scale the matrix by 2, the solution halves.
        values.iter_mut().for_each(|v| *v *= 2.0);
        chol.factorize(&values).unwrap();
        let mut rhs = vec![0.0; n];
        rhs[n - 1] = 1.0;
        chol.solve_in_place(&mut rhs).unwrap();
        assert!((rhs[n - 1] - n as f64 / 2.0).abs() < 1e-10);
    }

    #[test]
    fn custom_order_gives_the_same_solution_and_bad_orders_are_errors() {
        let n = 30;
        let mut dofs = vec![crate::linalg::pattern::CONSTRAINED, 0];
        for i in 0..n - 1 {
            dofs.extend([i, i + 1]);
        }
        let pattern = SymmetricPattern::new(n, 2, &dofs);
        let element_upper: Vec<f64> = (0..n).flat_map(|_| [1.0, -1.0, 1.0]).collect();
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&element_upper, &mut values);
        let reversed: Vec<usize> = (0..n).rev().collect();
        let mut chol = SparseCholesky::with_order(&pattern, 1, Some(&reversed)).unwrap();
        chol.factorize(&values).unwrap();
        let mut rhs = vec![0.0; n];
        rhs[n - 1] = 1.0;
        chol.solve_in_place(&mut rhs).unwrap();
        for (i, x) in rhs.iter().enumerate() {
            assert!((x - (i + 1) as f64).abs() < 1e-10);
        }
        let mut repeated = reversed.clone();
        repeated[0] = repeated[1];
        assert!(SparseCholesky::with_order(&pattern, 1, Some(&repeated)).is_err());
        assert!(SparseCholesky::with_order(&pattern, 1, Some(&reversed[1..])).is_err());
    }

    /// The hand-written supernodal solve (and the pre-permuted factorisation) on a 2D grid
    /// Laplacian large enough for faer to choose the supernodal factor, with AMD and a custom order:
    /// the residual `A x − b` is at round-off level.
    #[test]
    fn supernodal_solve_matches_the_matrix() {
        let side = 120;
        let node = |i: usize, j: usize| {
            if i == 0 { crate::linalg::pattern::CONSTRAINED } else { (i - 1) * side + j }
        };
        let mut dofs = Vec::new();
        for i in 0..side {
            for j in 0..side - 1 {
                // Two triangles per grid cell (P1 Laplacian of a unit right triangle).
                dofs.extend([node(i, j), node(i + 1, j), node(i + 1, j + 1)]);
                dofs.extend([node(i, j), node(i + 1, j + 1), node(i, j + 1)]);
            }
        }
        let n = side * side;
        let pattern = SymmetricPattern::new(n, 3, &dofs);
        let element = [1.0, -1.0, 0.0, 2.0, -1.0, 1.0];
        let upper: Vec<f64> = (0..dofs.len() / 3).flat_map(|_| element).collect();
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&upper, &mut values);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.4).collect();
        let reversed: Vec<usize> = (0..n).rev().collect();
        for order in [None, Some(reversed.as_slice())] {
            let mut chol = SparseCholesky::with_order(&pattern, 1, order).unwrap();
            // The banded (reversed natural) order has dense enough columns for supernodes.
            let supernodal = matches!(chol.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_));
            assert!(order.is_none() || supernodal);
            chol.factorize(&values).unwrap();
            let mut x = b.clone();
            chol.solve_in_place(&mut x).unwrap();
            let mut ax = vec![0.0; n];
            pattern.symmetric_mul(&values, &x, &mut ax);
            let error = ax.iter().zip(&b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
            let x_max = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!(x_max > 1.0 && error < 1e-10 * x_max, "residual {error}, |x| {x_max}");
            // The single-precision preconditioner is close to the inverse, not equal to it.
            let mut y = b.clone();
            chol.precondition_in_place(&mut y).unwrap();
            let gap = y.iter().zip(&x).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
            assert!(gap < 1e-4 * x_max && (!supernodal || gap > 0.0), "gap {gap}");
        }
    }

    /// With a nested-dissection order the elimination tree splits below the top separator, and
    /// the parallel subtree solve agrees with the sequential one to round-off.
    #[test]
    fn parallel_subtree_solve_matches_the_sequential_one() {
        let side = 150;
        let id = |i: usize, j: usize| j * side + i;
        let mut dofs = Vec::new();
        for j in 0..side - 1 {
            for i in 0..side - 1 {
                dofs.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                dofs.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let n = side * side;
        let pattern = SymmetricPattern::new(n, 3, &dofs);
        // Laplacian plus a small diagonal shift: positive definite without constraints.
        let element = [1.01, -1.0, 0.0, 2.01, -1.0, 1.01];
        let upper: Vec<f64> = (0..dofs.len() / 3).flat_map(|_| element).collect();
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&upper, &mut values);
        let xy: Vec<[f64; 2]> = (0..n).map(|v| [(v % side) as f64, (v / side) as f64]).collect();
        let order = crate::linalg::ordering::nested_dissection(&pattern, &xy);
        let mut chol = SparseCholesky::with_order(&pattern, 1, Some(&order)).unwrap();
        assert!(matches!(chol.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)));
        let plan = chol.subtree_plan.as_ref().expect("nested dissection splits the tree");
        assert!(plan.tasks.len() >= 2 && plan.top_start < n);
        chol.factorize(&values).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.4).collect();
        let solve_with = |threads: usize, chol: &mut SparseCholesky| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mut x = b.clone();
            pool.install(|| chol.solve_in_place(&mut x)).unwrap();
            x
        };
        let sequential = solve_with(1, &mut chol);
        let parallel = solve_with(2, &mut chol);
        // The fallback (faer's own solve) agrees with the supernodal walk.
        chol.set_faer_solve(true);
        let by_faer = solve_with(1, &mut chol);
        chol.set_faer_solve(false);
        let gap_faer =
            sequential.iter().zip(&by_faer).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
        assert!(gap_faer <= 1e-12 * sequential.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
        let x_max = sequential.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let gap = sequential.iter().zip(&parallel).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
        assert!(x_max > 0.1 && gap <= 1e-12 * x_max, "gap {gap}, |x| {x_max}");
        let mut ax = vec![0.0; n];
        pattern.symmetric_mul(&values, &parallel, &mut ax);
        let error = ax.iter().zip(&b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
        assert!(error < 1e-10, "residual {error}");
    }

    #[test]
    fn indefinite_matrix_is_an_error() {
        let pattern = SymmetricPattern::new(1, 1, &[0]);
        let mut chol = SparseCholesky::new(&pattern, 1).unwrap();
        assert!(chol.factorize(&[-1.0]).is_err());
    }
}
