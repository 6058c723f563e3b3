//! Essential (Dirichlet) constraints: which DOFs are free, and the values of the others.
//!
//! Constrained DOFs are eliminated from the linear and non-linear systems (condensation, as
//! scikit-fem's `condense`): a system is assembled and solved on the free DOFs only, the full DOF
//! vector carries the prescribed values at the constrained DOFs, and an element's contribution to a
//! constrained row is dropped while its constrained columns act through the residual (the
//! lifting). Free DOFs are numbered in increasing global order, so the numbering — and with it the
//! sparsity pattern and the elimination order — depends only on which DOFs are constrained.
//!
//! [`ConstraintsBuilder`] collects the constraints of a problem: the symmetry axis (`u = 0` there,
//! as the azimuthal potential of magnetostatics requires; a scalar field such as a temperature
//! leaves the axis free), tagged boundaries with a value function or kept at their value (zero
//! unless prescribed), and DOFs that belong to no element (constrained to zero). Where prescribed
//! values overlap (a corner shared by two boundaries), the last value prescribed wins.

use crate::discretisation::dofs::DofMap;
use crate::linalg::pattern::CONSTRAINED;

/// Which DOFs are free (with their index among the free DOFs) and the values of the constrained
/// ones.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraints {
    /// Free index of every global DOF, or [`CONSTRAINED`].
    free_index: Vec<usize>,
    /// Prescribed value of every constrained DOF (0 at free DOFs).
    values: Vec<f64>,
    n_free: usize,
}

impl Constraints {
    /// A builder over the DOFs of `dofs`: every DOF that belongs to an element starts free.
    pub fn builder(dofs: &DofMap) -> ConstraintsBuilder<'_> {
        let mut constrained = vec![true; dofs.len()];
        for &d in dofs.element_dofs() {
            constrained[d] = false;
        }
        ConstraintsBuilder { dofs, constrained, values: vec![0.0; dofs.len()] }
    }

    /// Number of free DOFs.
    pub fn n_free(&self) -> usize {
        self.n_free
    }

    /// Number of DOFs, free and constrained.
    pub fn len(&self) -> usize {
        self.free_index.len()
    }

    /// True when there are no DOFs at all.
    pub fn is_empty(&self) -> bool {
        self.free_index.is_empty()
    }

    /// The free index of every global DOF, or [`CONSTRAINED`].
    pub fn free_index(&self) -> &[usize] {
        &self.free_index
    }

    /// True when global DOF `dof` is free.
    #[inline]
    pub fn is_free(&self, dof: usize) -> bool {
        self.free_index[dof] != CONSTRAINED
    }

    /// The prescribed values (0 at free DOFs).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Sets the constrained entries of the full vector `u` to their prescribed values.
    pub fn impose(&self, u: &mut [f64]) {
        for ((value, &free), &prescribed) in u.iter_mut().zip(&self.free_index).zip(&self.values) {
            if free == CONSTRAINED {
                *value = prescribed;
            }
        }
    }

    /// The lifting: the prescribed values at the constrained DOFs, zero at the free ones.
    pub fn lifting(&self) -> Vec<f64> {
        self.values.clone()
    }

    /// The free-DOF indices of a list of global DOFs (e.g. all element DOF lists), with
    /// [`CONSTRAINED`] for constrained ones.
    pub fn free_dofs_of(&self, global: &[usize]) -> Vec<usize> {
        global.iter().map(|&d| self.free_index[d]).collect()
    }

    /// The values of the free DOFs of the full vector `u`.
    pub fn restrict(&self, u: &[f64]) -> Vec<f64> {
        let mut free = vec![0.0; self.n_free];
        for (&value, &d) in u.iter().zip(&self.free_index) {
            if d != CONSTRAINED {
                free[d] = value;
            }
        }
        free
    }

    /// The full vector with `free` at the free DOFs and zero at the constrained ones (e.g. a
    /// perturbation of the solution, which keeps the constrained values).
    pub fn extend_with_zeros(&self, free: &[f64]) -> Vec<f64> {
        self.free_index.iter().map(|&d| if d == CONSTRAINED { 0.0 } else { free[d] }).collect()
    }

    /// `[r, z]` of the free DOFs, in free order (e.g. for a geometric elimination order).
    pub fn free_coordinates(&self, dofs: &DofMap) -> Vec<[f64; 2]> {
        let coordinates = dofs.coordinates();
        (0..self.len()).filter(|&v| self.is_free(v)).map(|v| coordinates[v]).collect()
    }
}

/// Collects the constraints of a problem; see [`Constraints::builder`].
#[derive(Debug)]
pub struct ConstraintsBuilder<'a> {
    dofs: &'a DofMap,
    constrained: Vec<bool>,
    values: Vec<f64>,
}

impl ConstraintsBuilder<'_> {
    /// Constrains the DOFs on the symmetry axis `r = 0` ([`DofMap::axis_dofs`]) to `value`.
    pub fn axis(mut self, value: f64) -> Self {
        for d in self.dofs.axis_dofs() {
            self.constrained[d] = true;
            self.values[d] = value;
        }
        self
    }

    /// Constrains the DOFs of the edges tagged `tag` ([`DofMap::boundary_dofs`]) to the nodal
    /// interpolation of `g(r, z)` (its values at the vertices and, for P2, the edge midpoints).
    pub fn prescribe(mut self, tag: u32, g: impl Fn([f64; 2]) -> f64) -> Self {
        let coordinates = self.dofs.coordinates();
        for d in self.dofs.boundary_dofs(tag) {
            self.constrained[d] = true;
            self.values[d] = g(coordinates[d]);
        }
        self
    }

    /// Constrains the DOFs of the edges tagged `tag`, keeping the value already prescribed at a
    /// DOF shared with an earlier [`Self::prescribe`]d boundary and zero elsewhere (homogeneous
    /// Dirichlet).
    pub fn fix(mut self, tag: u32) -> Self {
        for d in self.dofs.boundary_dofs(tag) {
            self.constrained[d] = true;
        }
        self
    }

    /// Numbers the free DOFs in increasing global order.
    pub fn build(self) -> Constraints {
        let mut free_index = vec![CONSTRAINED; self.constrained.len()];
        let mut n_free = 0;
        for (index, &constrained) in free_index.iter_mut().zip(&self.constrained) {
            if !constrained {
                *index = n_free;
                n_free += 1;
            }
        }
        let mut values = self.values;
        for (value, &c) in values.iter_mut().zip(&self.constrained) {
            if !c {
                *value = 0.0;
            }
        }
        Constraints { free_index, values, n_free }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discretisation::dofs::ElementOrder;
    use crate::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
    use std::sync::Arc;

    fn map(order: ElementOrder) -> DofMap {
        let r = graded_lines(0.0, 1.0, 3, 1.0);
        let z = graded_lines(0.0, 1.0, 2, 1.0);
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        DofMap::new(Arc::new(rectangle_mesh(&r, &z, |_, _| 1, sides).unwrap()), order)
    }

    #[test]
    fn axis_and_boundary_values_and_free_numbering() {
        let dofs = map(ElementOrder::P2);
        let c = Constraints::builder(&dofs).prescribe(2, |p| 2.0 * p[1]).axis(0.0).build();
        let constrained = dofs.axis_dofs().len() + dofs.boundary_dofs(2).len();
        assert_eq!(c.n_free(), dofs.len() - constrained);
        // Free DOFs are numbered in global order.
        let free: Vec<usize> = (0..c.len()).filter(|&d| c.is_free(d)).collect();
        for (k, &d) in free.iter().enumerate() {
            assert_eq!(c.free_index()[d], k);
        }
        let mut u = vec![7.0; dofs.len()];
        c.impose(&mut u);
        for d in dofs.boundary_dofs(2) {
            assert!((u[d] - 2.0 * dofs.coordinates()[d][1]).abs() < 1e-15);
        }
        for d in dofs.axis_dofs() {
            assert!(u[d].abs() < 1e-15);
        }
        let restricted = c.restrict(&u);
        assert!(restricted.iter().all(|&v| (v - 7.0).abs() < 1e-15));
        let back = c.extend_with_zeros(&restricted);
        assert!(back.iter().zip(&u).all(|(b, u)| (b - u).abs() < 1e-15 || b.abs() < 1e-15));
    }

    /// The last value prescribed wins where constraints overlap (the corner of the axis and a
    /// boundary); a fixed boundary keeps an earlier prescribed value.
    #[test]
    fn last_prescribed_value_wins() {
        let dofs = map(ElementOrder::P1);
        let on_both = |a: &[usize], b: &[usize]| *a.iter().find(|d| b.contains(d)).unwrap();
        let corner = on_both(&dofs.axis_dofs(), &dofs.boundary_dofs(3));
        let c = Constraints::builder(&dofs).prescribe(3, |_| 5.0).axis(0.0).build();
        assert!(c.values()[corner].abs() < 1e-15);
        let corner = on_both(&dofs.boundary_dofs(2), &dofs.boundary_dofs(3));
        let c = Constraints::builder(&dofs).prescribe(3, |_| 5.0).fix(2).build();
        assert!((c.values()[corner] - 5.0).abs() < 1e-15 && !c.is_free(corner));
    }
}
