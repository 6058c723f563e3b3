//! Triangle elements: the affine (P1) triangle geometry and the Lagrange bases of order 1 and 2.
//!
//! Geometry: for a triangle with nodes `x_1, x_2, x_3` (counter-clockwise) the barycentric
//! coordinate `λ_i = (a_i + b_i r + c_i z) / (2|T|)` with `b_i = z_j − z_k`, `c_i = r_k − r_j` for
//! the cyclic triple `(i, j, k)` (e.g. Zienkiewicz & Taylor, The Finite Element Method, vol. 1,
//! §4.2). Elements are straight-sided: the map from barycentric coordinates to `(r, z)` is affine
//! for both orders ([`P1Triangle`]).
//!
//! Bases, written in barycentric (area) coordinates (Zienkiewicz, Taylor & Zhu, The Finite Element
//! Method: Its Basis and Fundamentals, 7th ed., 2013, §6.2.1 "Shape functions for triangles"):
//! - [`ElementTriP1`]: `N_i = λ_i`, `i = 0, 1, 2` (the vertices);
//! - [`ElementTriP2`]: vertices `N_i = λ_i (2λ_i − 1)` and mid-side nodes `N_{3+k} = 4 λ_k λ_{k+1}`
//!   on the edge from vertex `k` to vertex `k + 1 (mod 3)`, i.e. local DOFs 3, 4, 5 sit on the edges
//!   (0, 1), (1, 2), (2, 0). Gradients by the chain rule, `∇N = Σ_m ∂N/∂λ_m ∇λ_m`:
//!   `∇N_i = (4λ_i − 1) ∇λ_i`, `∇N_{3+k} = 4 (λ_{k+1} ∇λ_k + λ_k ∇λ_{k+1})`.
//!
//! Both implement [`TriangleBasis`], whose const parameter is the number of local DOFs, so a form
//! written once as a generic function is compiled to fixed-size loops for each order.

/// A Lagrange basis on the triangle with `N` local degrees of freedom, evaluated from barycentric
/// coordinates and the (constant) barycentric gradients of the affine geometry.
pub trait TriangleBasis<const N: usize> {
    /// Polynomial order of the basis (1 or 2).
    const ORDER: usize;

    /// Basis values `N_i(λ)`.
    fn values(bary: [f64; 3]) -> [f64; N];

    /// Basis gradients `∇N_i = [∂N_i/∂r, ∂N_i/∂z]` (1/m) at `λ`, from `grad_lambda[m] = ∇λ_m`.
    fn gradients(bary: [f64; 3], grad_lambda: &[[f64; 2]; 3]) -> [[f64; 2]; N];

    /// Barycentric coordinates of the local DOF nodes (vertices, then edge midpoints for P2).
    fn nodes() -> [[f64; 3]; N];
}

/// The linear Lagrange triangle: three vertex DOFs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ElementTriP1;

/// The quadratic Lagrange triangle: three vertex DOFs, then the midpoints of the edges (0, 1),
/// (1, 2), (2, 0).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ElementTriP2;

/// Local vertex pairs of the P2 edge DOFs 3, 4, 5.
pub const P2_EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];

impl TriangleBasis<3> for ElementTriP1 {
    const ORDER: usize = 1;

    #[inline(always)]
    fn values(bary: [f64; 3]) -> [f64; 3] {
        bary
    }

    #[inline(always)]
    fn gradients(_bary: [f64; 3], grad_lambda: &[[f64; 2]; 3]) -> [[f64; 2]; 3] {
        *grad_lambda
    }

    fn nodes() -> [[f64; 3]; 3] {
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    }
}

impl TriangleBasis<6> for ElementTriP2 {
    const ORDER: usize = 2;

    #[inline(always)]
    fn values(l: [f64; 3]) -> [f64; 6] {
        [
            l[0] * (2.0 * l[0] - 1.0),
            l[1] * (2.0 * l[1] - 1.0),
            l[2] * (2.0 * l[2] - 1.0),
            4.0 * l[0] * l[1],
            4.0 * l[1] * l[2],
            4.0 * l[2] * l[0],
        ]
    }

    #[inline(always)]
    fn gradients(l: [f64; 3], g: &[[f64; 2]; 3]) -> [[f64; 2]; 6] {
        let vertex = |i: usize| {
            let c = 4.0 * l[i] - 1.0;
            [c * g[i][0], c * g[i][1]]
        };
        let edge = |i: usize, j: usize| {
            [4.0 * (l[j] * g[i][0] + l[i] * g[j][0]), 4.0 * (l[j] * g[i][1] + l[i] * g[j][1])]
        };
        [vertex(0), vertex(1), vertex(2), edge(0, 1), edge(1, 2), edge(2, 0)]
    }

    fn nodes() -> [[f64; 3]; 6] {
        [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.5],
            [0.5, 0.0, 0.5],
        ]
    }
}

/// Geometry of one P1 triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct P1Triangle {
    /// Node coordinates `[r, z]`.
    pub nodes: [[f64; 2]; 3],
    /// Area (m²), positive for a counter-clockwise triangle.
    pub area: f64,
    /// `∇λ_i = [∂λ_i/∂r, ∂λ_i/∂z]` (1/m), constant over the triangle.
    pub grad: [[f64; 2]; 3],
}

impl P1Triangle {
    /// Builds the geometry from the three node coordinates.
    pub fn new(nodes: [[f64; 2]; 3]) -> Self {
        let [p1, p2, p3] = nodes;
        let two_area = (p2[0] - p1[0]) * (p3[1] - p1[1]) - (p3[0] - p1[0]) * (p2[1] - p1[1]);
        let inv = 1.0 / two_area;
        let grad = [
            [(p2[1] - p3[1]) * inv, (p3[0] - p2[0]) * inv],
            [(p3[1] - p1[1]) * inv, (p1[0] - p3[0]) * inv],
            [(p1[1] - p2[1]) * inv, (p2[0] - p1[0]) * inv],
        ];
        Self { nodes, area: 0.5 * two_area, grad }
    }

    /// Physical point `[r, z]` of the barycentric coordinates `bary`.
    pub fn point(&self, bary: [f64; 3]) -> [f64; 2] {
        let mut p = [0.0; 2];
        for i in 0..3 {
            p[0] += bary[i] * self.nodes[i][0];
            p[1] += bary[i] * self.nodes[i][1];
        }
        p
    }

    /// Barycentric coordinates of the physical point `p` (outside the triangle some are negative).
    pub fn barycentric(&self, p: [f64; 2]) -> [f64; 3] {
        let mut l = [0.0; 3];
        for i in 0..3 {
            let j = (i + 1) % 3;
            let k = (i + 2) % 3;
            // λ_i = area(p, x_j, x_k) / area(T).
            let (a, b) = (self.nodes[j], self.nodes[k]);
            l[i] =
                0.5 * ((a[0] - p[0]) * (b[1] - p[1]) - (b[0] - p[0]) * (a[1] - p[1])) / self.area;
        }
        l
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradients_reproduce_linear_functions() {
        let t = P1Triangle::new([[0.1, 0.2], [0.5, 0.25], [0.2, 0.7]]);
        assert!(t.area > 0.0);
        // f = 3 + 2r − 5z sampled at the nodes has gradient (2, −5).
        let f: Vec<f64> = t.nodes.iter().map(|p| 3.0 + 2.0 * p[0] - 5.0 * p[1]).collect();
        let g = (0..3)
            .fold([0.0, 0.0], |g, i| [g[0] + f[i] * t.grad[i][0], g[1] + f[i] * t.grad[i][1]]);
        assert!((g[0] - 2.0).abs() < 1e-12 && (g[1] + 5.0).abs() < 1e-12);
        let p = t.point([0.2, 0.3, 0.5]);
        let l = t.barycentric(p);
        assert!(
            (l[0] - 0.2).abs() < 1e-12 && (l[1] - 0.3).abs() < 1e-12 && (l[2] - 0.5).abs() < 1e-12
        );
    }

    /// Points spread over the triangle (barycentric), including vertices and edge points.
    fn sample_points() -> Vec<[f64; 3]> {
        let mut points = Vec::new();
        for i in 0..=6 {
            for j in 0..=(6 - i) {
                let (a, b) = (i as f64 / 6.0, j as f64 / 6.0);
                points.push([a, b, 1.0 - a - b]);
            }
        }
        points.push([0.21, 0.37, 0.42]);
        points
    }

    /// Kronecker property `N_i(x_j) = δ_ij` at the element's own nodes.
    fn check_kronecker<E: TriangleBasis<N>, const N: usize>() {
        for (j, node) in E::nodes().iter().enumerate() {
            let v = E::values(*node);
            for i in 0..N {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((v[i] - expected).abs() < 1e-15, "N_{i}(x_{j}) = {}", v[i]);
            }
        }
    }

    /// Interpolating `f` at the element nodes reproduces `f` and its gradient everywhere when `f`
    /// is in the element's polynomial space; the basis sums to one and its gradients to zero.
    fn check_reproduction<E: TriangleBasis<N>, const N: usize>(
        f: impl Fn([f64; 2]) -> f64,
        grad_f: impl Fn([f64; 2]) -> [f64; 2],
    ) {
        let t = P1Triangle::new([[0.1, 0.2], [0.5, 0.25], [0.2, 0.7]]);
        let coefficients = E::nodes().map(|node| f(t.point(node)));
        for bary in sample_points() {
            let values = E::values(bary);
            let gradients = E::gradients(bary, &t.grad);
            let sum: f64 = values.iter().sum();
            let grad_sum = gradients.iter().fold([0.0, 0.0], |s, g| [s[0] + g[0], s[1] + g[1]]);
            assert!((sum - 1.0).abs() < 1e-14, "partition of unity: {sum}");
            assert!(grad_sum[0].abs() < 1e-12 && grad_sum[1].abs() < 1e-12, "{grad_sum:?}");
            let p = t.point(bary);
            let value: f64 = (0..N).map(|i| coefficients[i] * values[i]).sum();
            let grad = (0..N).fold([0.0, 0.0], |g, i| {
                [g[0] + coefficients[i] * gradients[i][0], g[1] + coefficients[i] * gradients[i][1]]
            });
            let (exact, exact_grad) = (f(p), grad_f(p));
            assert!((value - exact).abs() < 1e-13, "{value} vs {exact} at {p:?}");
            for k in 0..2 {
                assert!(
                    (grad[k] - exact_grad[k]).abs() < 1e-12,
                    "gradient {grad:?} vs {exact_grad:?} at {p:?}"
                );
            }
        }
    }

    #[test]
    fn p1_basis_reproduces_linear_functions() {
        check_kronecker::<ElementTriP1, 3>();
        check_reproduction::<ElementTriP1, 3>(|p| 3.0 + 2.0 * p[0] - 5.0 * p[1], |_| [2.0, -5.0]);
    }

    #[test]
    fn p2_basis_reproduces_quadratics() {
        check_kronecker::<ElementTriP2, 6>();
        let f = |p: [f64; 2]| {
            let (r, z) = (p[0], p[1]);
            1.5 - 2.0 * r + 0.7 * z + 3.0 * r * r - 4.0 * r * z + 2.5 * z * z
        };
        let grad_f = |p: [f64; 2]| {
            let (r, z) = (p[0], p[1]);
            [-2.0 + 6.0 * r - 4.0 * z, 0.7 - 4.0 * r + 5.0 * z]
        };
        check_reproduction::<ElementTriP2, 6>(f, grad_f);
    }

    /// A cubic is not reproduced by P2: the test above could fail.
    #[test]
    fn p2_basis_does_not_reproduce_a_cubic() {
        let t = P1Triangle::new([[0.1, 0.2], [0.5, 0.25], [0.2, 0.7]]);
        let f = |p: [f64; 2]| p[0] * p[0] * p[0];
        let coefficients = ElementTriP2::nodes().map(|node| f(t.point(node)));
        let bary = [0.21, 0.37, 0.42];
        let values = ElementTriP2::values(bary);
        let value: f64 = (0..6).map(|i| coefficients[i] * values[i]).sum();
        assert!((value - f(t.point(bary))).abs() > 1e-5);
    }
}
