//! The first-order (P1) triangle: barycentric coordinates, their constant gradients and the area.
//!
//! For a triangle with nodes `x_1, x_2, x_3` (counter-clockwise) the barycentric coordinate
//! `λ_i = (a_i + b_i r + c_i z) / (2|T|)` with `b_i = z_j − z_k`, `c_i = r_k − r_j` for the cyclic
//! triple `(i, j, k)` (e.g. Zienkiewicz & Taylor, The Finite Element Method, vol. 1, §4.2).

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
}
