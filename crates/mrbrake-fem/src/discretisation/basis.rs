//! The basis: a mesh, an element order, a quadrature rule and the integration weight — what a form
//! needs at every quadrature point of every element, and nothing about physics.
//!
//! As in scikit-fem (`Basis(mesh, element, quadrature)`), a [`Basis`] ties the DOF numbering of one
//! element order ([`DofMap`]) to a triangle quadrature rule and gives, per element and quadrature
//! point, the basis values `φ_i`, their gradients `∇φ_i`, the point `(r, z)` and the weight. For the
//! axisymmetric problems of mrbrake ([`Weighting::Axisymmetric`]) the weight carries the radius,
//! `w_q |T| r_q`, so that `Σ_q weight · f(x_q)` approximates `∫_T f r dr dz` — the volume integral
//! over the ring swept by the triangle divided by 2π (e.g. Silvester & Ferrari, *Finite Elements for
//! Electrical Engineers*, 3rd ed., §7.4). [`Weighting::Planar`] drops the radius (2D problems).
//!
//! The values are computed on the fly from the element's affine geometry (no per-point tables:
//! measured, recomputing them costs less than reading them back from memory on the 100 k-element
//! benchmark), and forms are generic over the Lagrange basis ([`TriangleBasis`]) so that each
//! element order compiles to fixed-size loops:
//!
//! ```
//! use std::sync::Arc;
//! use mrbrake_fem::discretisation::basis::{Basis, Weighting};
//! use mrbrake_fem::discretisation::dofs::ElementOrder;
//! use mrbrake_fem::discretisation::element::ElementTriP1;
//! use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
//!
//! let r = graded_lines(0.0, 1.0, 4, 1.0);
//! let z = graded_lines(0.0, 1.0, 4, 1.0);
//! let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
//! let mesh = Arc::new(rectangle_mesh(&r, &z, |_, _| 1, sides).unwrap());
//! let basis = Basis::new(mesh, ElementOrder::P1, 2, Weighting::Axisymmetric);
//! // ∫ r dr dz over the unit square is 1/2: the weights of all points sum to it.
//! let mut volume = 0.0;
//! for t in 0..basis.n_elements() {
//!     let element = basis.element::<ElementTriP1, 3>(t);
//!     let geometry = element.geometry();
//!     volume += element.points(&geometry).map(|q| q.weight).sum::<f64>();
//! }
//! assert!((volume - 0.5).abs() < 1e-12);
//! ```

use std::marker::PhantomData;
use std::sync::Arc;

use crate::discretisation::dofs::{DofMap, ElementOrder};
use crate::discretisation::element::{P1Triangle, TriangleBasis};
use crate::discretisation::quadrature::{TrianglePoint, triangle_rule};
use crate::mesh::Mesh;

/// How the quadrature weight is scaled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Weighting {
    /// Planar 2D integrals: weight `w_q |T|`.
    Planar,
    /// Axisymmetric integrals `∫ f r dr dz` (the ring volume over 2π): weight `w_q |T| r_q`.
    Axisymmetric,
}

/// The values a form needs at one quadrature point of one element with `N` local DOFs.
#[derive(Debug, Clone, Copy)]
pub struct QuadraturePoint<const N: usize> {
    /// `[r, z]` of the point (m).
    pub point: [f64; 2],
    /// Quadrature weight: `w_q |T|`, times `r` for [`Weighting::Axisymmetric`].
    pub weight: f64,
    /// Basis values `φ_i`.
    pub phi: [f64; N],
    /// Basis gradients `∇φ_i = [∂φ_i/∂r, ∂φ_i/∂z]` (1/m).
    pub grad: [[f64; 2]; N],
}

/// A mesh with a DOF numbering, a quadrature rule and a weighting.
#[derive(Debug, Clone)]
pub struct Basis {
    dofs: DofMap,
    rule: Vec<TrianglePoint>,
    weighting: Weighting,
}

impl Basis {
    /// The basis of `order` on `mesh` with the symmetric triangle rule exact to `quadrature_degree`
    /// ([`triangle_rule`]) and the given weighting. The mesh should pass [`Mesh::validate`].
    pub fn new(
        mesh: Arc<Mesh>,
        order: ElementOrder,
        quadrature_degree: usize,
        weighting: Weighting,
    ) -> Self {
        Self::with_dofs(DofMap::new(mesh, order), quadrature_degree, weighting)
    }

    /// The basis of an existing DOF numbering.
    pub fn with_dofs(dofs: DofMap, quadrature_degree: usize, weighting: Weighting) -> Self {
        Self { dofs, rule: triangle_rule(quadrature_degree), weighting }
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh> {
        self.dofs.mesh()
    }

    /// The DOF numbering.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// The element order.
    pub fn order(&self) -> ElementOrder {
        self.dofs.order()
    }

    /// The triangle quadrature rule.
    pub fn rule(&self) -> &[TrianglePoint] {
        &self.rule
    }

    /// The weighting of the quadrature.
    pub fn weighting(&self) -> Weighting {
        self.weighting
    }

    /// Number of elements (mesh triangles).
    pub fn n_elements(&self) -> usize {
        self.dofs.mesh().triangles.len()
    }

    /// The straight-sided geometry of element `t` (always inlined: in element loops a call costs
    /// as much as the geometry itself).
    #[inline(always)]
    pub fn geometry(&self, t: usize) -> P1Triangle {
        let mesh = self.dofs.mesh();
        let [a, b, c] = mesh.triangles[t];
        P1Triangle::new([mesh.nodes[a], mesh.nodes[b], mesh.nodes[c]])
    }

    /// The basis `E`'s values at quadrature point `q` of the triangle `geometry`.
    #[inline]
    pub fn point<E: TriangleBasis<N>, const N: usize>(
        &self,
        geometry: &P1Triangle,
        q: &TrianglePoint,
    ) -> QuadraturePoint<N> {
        let point = geometry.point(q.bary);
        let weight = match self.weighting {
            Weighting::Planar => q.weight * geometry.area,
            Weighting::Axisymmetric => q.weight * geometry.area * point[0],
        };
        let phi = E::values(q.bary);
        let grad = E::gradients(q.bary, &geometry.grad);
        QuadraturePoint { point, weight, phi, grad }
    }

    /// Element `t` seen through the basis `E` with `N` local DOFs (which must match the order).
    #[inline(always)]
    pub fn element<E: TriangleBasis<N>, const N: usize>(&self, t: usize) -> Element<'_, E, N> {
        debug_assert_eq!(N, self.dofs.dofs_per_triangle(), "basis with {N} DOFs on this order");
        Element { index: t, basis: self, element: PhantomData }
    }
}

/// One element of a [`Basis`] with the Lagrange basis `E` (`N` local DOFs): its index, DOFs,
/// geometry and quadrature points. Cheap to make: nothing is computed until asked.
#[derive(Debug)]
pub struct Element<'a, E, const N: usize> {
    /// Index of the element (mesh triangle).
    pub index: usize,
    basis: &'a Basis,
    element: PhantomData<E>,
}

impl<'a, E: TriangleBasis<N>, const N: usize> Element<'a, E, N> {
    /// The basis this element belongs to.
    #[inline(always)]
    pub fn basis(&self) -> &'a Basis {
        self.basis
    }

    /// The global DOFs of the element, in local order.
    #[inline(always)]
    pub fn dofs(&self) -> &'a [usize; N] {
        let all = self.basis.dofs.element_dofs();
        all[N * self.index..N * (self.index + 1)].try_into().expect("N DOFs per element")
    }

    /// The straight-sided geometry of the element.
    #[inline(always)]
    pub fn geometry(&self) -> P1Triangle {
        self.basis.geometry(self.index)
    }

    /// The physical tag (region) of the element.
    #[inline(always)]
    pub fn tag(&self) -> u32 {
        self.basis.mesh().triangle_tags[self.index]
    }

    /// The quadrature points of the element with the geometry `geometry` (from
    /// [`Self::geometry`]; passed in so that a form computes it once).
    #[inline]
    pub fn points<'g>(
        &self,
        geometry: &'g P1Triangle,
    ) -> impl Iterator<Item = QuadraturePoint<N>> + use<'a, 'g, E, N> {
        let basis = self.basis;
        basis.rule.iter().map(move |q| basis.point::<E, N>(geometry, q))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discretisation::element::ElementTriP2;
    use crate::mesh::structured::{SideTags, graded_lines, rectangle_mesh};

    fn square(order: ElementOrder, weighting: Weighting) -> Basis {
        let r = graded_lines(0.5, 1.5, 3, 1.3);
        let z = graded_lines(0.0, 2.0, 4, 1.0);
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        let mesh = Arc::new(rectangle_mesh(&r, &z, |_, _| 1, sides).unwrap());
        Basis::new(mesh, order, 4, weighting)
    }

    /// `∫ r² dr dz` over [0.5, 1.5] × [0, 2] is 2 (1.5³ − 0.5³)/3 = 13/6, and `∫ r dr dz` is 2:
    /// the axisymmetric weights integrate `r` exactly, the planar ones the plain area.
    #[test]
    fn weights_integrate_the_radius() {
        for (weighting, f, exact) in [
            (Weighting::Axisymmetric, 1, 13.0 / 6.0),
            (Weighting::Planar, 2, 13.0 / 6.0),
            (Weighting::Planar, 0, 2.0),
        ] {
            let basis = square(ElementOrder::P2, weighting);
            let mut sum = 0.0;
            for t in 0..basis.n_elements() {
                let element = basis.element::<ElementTriP2, 6>(t);
                let geometry = element.geometry();
                sum +=
                    element.points(&geometry).map(|q| q.weight * q.point[0].powi(f)).sum::<f64>();
            }
            assert!((sum - exact).abs() < 1e-12, "{weighting:?} r^{f}: {sum} vs {exact}");
        }
    }

    /// The basis values at the points sum to one (partition of unity) and the element DOFs are the
    /// DOF map's.
    #[test]
    fn element_values_and_dofs() {
        let basis = square(ElementOrder::P2, Weighting::Axisymmetric);
        let element = basis.element::<ElementTriP2, 6>(3);
        assert_eq!(&element.dofs()[..], basis.dofs().element(3));
        let geometry = element.geometry();
        for q in element.points(&geometry) {
            assert!((q.phi.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        }
        assert_eq!(element.tag(), 1);
    }
}
