//! Electromagnetic forces on regions: the axial force on a body of revolution.
//!
//! **Virtual work on a shell ("eggshell") of elements.** The force on a body is the flux of the
//! Maxwell stress tensor through any surface that encloses it in the surrounding medium,
//! `F = ∮ T·n dS` with `T_ij = H_i B_j − δ_ij w'(H)` (`w' = ∫₀^H B·dH'` the co-energy density;
//! for a linear medium `T = (BB − ½B² I)/μ`). A surface integral of a finite-element field
//! depends strongly on where the surface runs; the robust discrete form spreads it over one layer
//! of elements. With a function `g` that is 1 on the body and 0 beyond the layer,
//! `∮ T·n dS = −∫ T·∇g dV`, so
//!
//! `F_z = −∫ (T_zr ∂g/∂r + T_zz ∂g/∂z) 2π r dr dz`, `T_zr = H_z B_r`, `T_zz = H_z B_z − w'`.
//!
//! With `g = Σ φ_i` over the body's nodes (the linear hat functions), `∇g` is non-zero only in the
//! elements outside the body that touch it, and the formula is exactly Coulomb's virtual work for
//! a rigid displacement of the body's nodes (J. L. Coulomb, "A methodology for the determination
//! of global electromechanical quantities from a finite element analysis and its application to
//! the evaluation of magnetic forces, torques and stiffness", IEEE Trans. Magn. 19(6), 1983,
//! 2514–2519, eq. 13 for a linear layer; the co-energy form for non-linear media, his eq. 9), also
//! known as the eggshell method (F. Henrotte, G. Deliége, K. Hameyer, "The eggshell approach for
//! the computation of electromagnetic forces in 2D and 3D", COMPEL 23(4), 2004, 996–1005). It
//! includes the Lorentz force `J × B` on the body's own currents and on eddy currents inside it.
//!
//! In an axisymmetric field only the axial component of the total force is non-zero (the radial
//! parts cancel around the circumference). [`Solver::lorentz_force_z`] gives the Lorentz force
//! `F_z = −∫ J_φ B_r dV` of a current-carrying region in air, an independent check (the tests
//! compare both with the closed form of two coaxial coils and with the co-energy derivative of a
//! pot core across its air gap).
//!
//! Where the layer carries a source current (a body beside a coil), the stress is not
//! divergence-free there (`∇·T = J × B`), and `−∫ T·∇g dV` would add the Lorentz force on those
//! currents weighted by `g`; that term, `−∫ g (J × B)_z dV = ∫ g J_φ B_r dV`, is taken off
//! (the force on the pot core and on its coil then cancel, `tests/it/problem_file.rs`).
//!
//! Limits: the layer must lie in a medium whose law is a function of the local field (air, the
//! MR fluid, steel): a body pressed against another body (no layer of a third medium between
//! them) has a contact force that no field formula gives. Eddy currents in a conducting layer
//! (a transient) are not taken off as the source currents are: choose bodies whose neighbours
//! do not conduct, or read the force of the conductor together with the body. The force of a harmonic phasor pair
//! is its time average (`⟨H_i B_j⟩ = ½ Re(H_i B_j*)`, linear media).

use mrbrake_fem::discretisation::element::P1Triangle;

use crate::MagneticsError;
use crate::field::Solution;
use crate::problem::Source;
use crate::solver::Solver;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// The elements of the layer around a body (the support of `∇g`), see [`Solver::force_layer`].
#[derive(Debug, Clone)]
pub(crate) struct ForceLayer {
    elements: Vec<LayerElement>,
}

/// One layer element: its triangle, the constant `∇g` on it, which of its vertices are the
/// body's, and its source current density `J_φ` (A/m², 0 without a source).
#[derive(Debug, Clone, Copy)]
struct LayerElement {
    triangle: usize,
    grad_g: [f64; 2],
    inside: [bool; 3],
    source: f64,
}

impl Solver {
    /// Axial force (N) on the body made of the regions `tags` (e.g. a rotor's parts), by virtual
    /// work on the layer of elements around it (module docs); positive along +z.
    pub fn axial_force(&self, solution: &Solution, tags: &[u32]) -> Result<f64, MagneticsError> {
        self.axial_force_averaged(&[(solution, 1.0)], tags)
    }

    /// Time-averaged axial force (N) of the harmonic field `Re{(re + j im) e^{jωt}}` (linear
    /// media): `½` of the force of the real part plus `½` of that of the imaginary part, since
    /// the stress is quadratic in the field and `⟨cos²⟩ = ⟨sin²⟩ = ½`, `⟨cos sin⟩ = 0`.
    pub fn axial_force_time_averaged(
        &self,
        re: &Solution,
        im: &Solution,
        tags: &[u32],
    ) -> Result<f64, MagneticsError> {
        self.axial_force_averaged(&[(re, 0.5), (im, 0.5)], tags)
    }

    /// `Σ weight × F_z(solution)` over `parts`.
    fn axial_force_averaged(
        &self,
        parts: &[(&Solution, f64)],
        tags: &[u32],
    ) -> Result<f64, MagneticsError> {
        let layer = self.force_layer(tags)?;
        Ok(self.layer_axial_force(&layer, parts))
    }

    /// The layer of elements around the body made of the regions `tags`: what depends on the
    /// mesh only, so a transient builds it once per body and evaluates it at every level.
    pub(crate) fn force_layer(&self, tags: &[u32]) -> Result<ForceLayer, MagneticsError> {
        let body = self.body_nodes(tags)?;
        let mesh = &self.problem.mesh;
        let mut elements = Vec::new();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let inside = tri.map(|v| body[v]);
            if tags.contains(&mesh.triangle_tags[t]) || !inside.iter().any(|&b| b) {
                continue;
            }
            let geometry = P1Triangle::new(tri.map(|v| mesh.nodes[v]));
            let mut grad_g = [0.0; 2];
            for k in (0..3).filter(|&k| inside[k]) {
                grad_g[0] += geometry.grad[k][0];
                grad_g[1] += geometry.grad[k][1];
            }
            let source = self.source_current_density(mesh.triangle_tags[t]);
            elements.push(LayerElement { triangle: t, grad_g, inside, source });
        }
        Ok(ForceLayer { elements })
    }

    /// `Σ weight × F_z(solution)` over `parts` on a layer built by [`Solver::force_layer`].
    pub(crate) fn layer_axial_force(&self, layer: &ForceLayer, parts: &[(&Solution, f64)]) -> f64 {
        let mut force = 0.0;
        for e in &layer.elements {
            for &(solution, weight) in parts {
                force +=
                    weight * self.layer_force(solution, e.triangle, e.grad_g, (e.inside, e.source));
            }
        }
        force
    }

    /// `−∫ (T_zr ∂g/∂r + T_zz ∂g/∂z) dV` over triangle `t` with the constant `∇g`, plus
    /// `∫ g J_φ B_r dV` when the triangle carries a source current density `J_φ` (module docs:
    /// the Lorentz force on currents in the layer is not the body's). `inside` says which of the
    /// triangle's vertices belong to the body (`g` = the sum of their hat functions).
    fn layer_force(
        &self,
        solution: &Solution,
        t: usize,
        grad_g: [f64; 2],
        (inside, source): ([bool; 3], f64),
    ) -> f64 {
        let material = self.form.material(t);
        let rule = self.basis().rule();
        let mut sum = 0.0;
        let mut point = 0;
        self.for_each_sample(t, rule, solution.a_phi(), |s| {
            if source != 0.0 {
                let g: f64 = (0..3).filter(|&k| inside[k]).map(|k| rule[point].bary[k]).sum();
                sum += TWO_PI * s.weight * g * source * s.b[0];
                point += 1;
            }
            let b2 = s.b[0] * s.b[0] + s.b[1] * s.b[1];
            let nu = material.nu_and_dnu_db2(b2).0;
            let h_z = nu * s.b[1];
            let co_energy = nu * b2 - material.energy_density(b2.sqrt());
            let t_zr = h_z * s.b[0];
            let t_zz = h_z * s.b[1] - co_energy;
            sum -= TWO_PI * s.weight * (t_zr * grad_g[0] + t_zz * grad_g[1]);
        });
        sum
    }

    /// Which mesh nodes belong to the regions `tags` (an input error for an unknown tag or an
    /// empty list).
    fn body_nodes(&self, tags: &[u32]) -> Result<Vec<bool>, MagneticsError> {
        if tags.is_empty() {
            return Err(MagneticsError::field("regions", "a force needs at least one region"));
        }
        for &tag in tags {
            if self.problem.region(tag).is_none() {
                return Err(MagneticsError::field(
                    "regions",
                    format!("force on region {tag}: no region with physical = {tag}"),
                ));
            }
        }
        let mesh = &self.problem.mesh;
        let mut body = vec![false; mesh.nodes.len()];
        for (tri, tag) in mesh.triangles.iter().zip(&mesh.triangle_tags) {
            if tags.contains(tag) {
                tri.iter().for_each(|&v| body[v] = true);
            }
        }
        Ok(body)
    }

    /// The Lorentz force `F_z = −∫ J_φ B_r dV` (N) on the source current of region `tag` (0 for a
    /// region without a source): `(J e_φ × B)_z = −J_φ B_r`.
    pub fn lorentz_force_z(&self, solution: &Solution, tag: u32) -> Result<f64, MagneticsError> {
        let region = self.problem.region(tag).ok_or_else(|| {
            MagneticsError::field(
                "regions",
                format!("force on region {tag}: no region with physical = {tag}"),
            )
        })?;
        if region.source.is_none() {
            return Ok(0.0);
        }
        let j = self.source_current_density(tag);
        let mesh = &self.problem.mesh;
        let mut force = 0.0;
        for t in (0..mesh.triangles.len()).filter(|&t| mesh.triangle_tags[t] == tag) {
            self.for_each_sample(t, self.basis().rule(), solution.a_phi(), |s| {
                force -= TWO_PI * s.weight * j * s.b[0];
            });
        }
        Ok(force)
    }

    /// The source current density `J_φ` (A/m²) of region `tag` (0 without a source).
    fn source_current_density(&self, tag: u32) -> f64 {
        match self.problem.region(tag).and_then(|r| r.source) {
            None => 0.0,
            Some(Source::CurrentDensity { a_per_m2 }) => a_per_m2,
            Some(Source::Coil { turns, current_a }) => turns * current_a / self.region_area_of(tag),
        }
    }

    /// Cross-section area (m²) of region `tag` (0 when absent).
    fn region_area_of(&self, tag: u32) -> f64 {
        self.problem
            .regions
            .iter()
            .position(|r| r.tag == tag)
            .map_or(0.0, |ri| self.region_area[ri])
    }
}
