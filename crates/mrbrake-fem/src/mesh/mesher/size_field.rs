//! The target element size: a global maximum, per-region targets, and smooth growth away from
//! finely meshed regions.
//!
//! The size (target edge length) at a point x lying in the region tagged t is
//!
//! ```text
//! h(x) = min( h_max, h_t, min_j ( h_j + growth * dist(x, boundary of region j) ) )
//! ```
//!
//! over every region j that has its own target h_j < h_max. The last term is a Lipschitz
//! (graded) extension of the region targets: the size grows linearly, at `growth` metres per metre,
//! away from a thin fluid gap, so the mesh coarsens gradually instead of jumping from the gap's
//! size to the global maximum across one element (which would spoil triangle quality and the field
//! accuracy next to the gap).

use std::collections::BTreeMap;

use crate::FemError;
use mrbrake_error::FieldError;

/// Size field parameters, in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct SizeField {
    /// Largest allowed edge length anywhere (m).
    pub max_edge_m: f64,
    /// Target edge length inside given regions, by physical tag (m).
    pub region_edge_m: BTreeMap<u32, f64>,
    /// Growth rate of the size away from a finer region (m of size per m of distance), > 0.
    pub growth: f64,
}

impl SizeField {
    /// A uniform field: every edge at most `max_edge_m`, growth 0.3.
    pub fn uniform(max_edge_m: f64) -> Self {
        Self { max_edge_m, region_edge_m: BTreeMap::new(), growth: 0.3 }
    }

    /// Sets the target edge length of one region (builder style).
    pub fn with_region(mut self, tag: u32, edge_m: f64) -> Self {
        self.region_edge_m.insert(tag, edge_m);
        self
    }

    /// Checks that every length is finite and positive and the growth rate is positive.
    pub fn validate(&self) -> Result<(), FemError> {
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !positive(self.max_edge_m) {
            let e = FieldError::out_of_range("max_edge_m", self.max_edge_m, "finite, > 0 m");
            return Err(e.into());
        }
        for (tag, h) in &self.region_edge_m {
            if !positive(*h) {
                let e =
                    FieldError::out_of_range(format!("region_edge_m[{tag}]"), h, "finite, > 0 m");
                return Err(e.into());
            }
        }
        if !(self.growth.is_finite() && self.growth > 0.0) {
            let e = FieldError::out_of_range("growth", self.growth, "finite, > 0 (typ. 0.1 to 1)");
            return Err(e.into());
        }
        Ok(())
    }

    /// The target of one region, capped by the global maximum.
    pub fn region_target(&self, tag: u32) -> f64 {
        self.region_edge_m.get(&tag).copied().unwrap_or(self.max_edge_m).min(self.max_edge_m)
    }
}

/// The boundary segments of one finely meshed region, for the graded distance term.
#[derive(Debug, Clone)]
pub(crate) struct FineRegion {
    /// Target edge length inside the region (m).
    pub edge_m: f64,
    /// Boundary segments `[p, q]`.
    pub segments: Vec<[[f64; 2]; 2]>,
    /// Bounding box `[rmin, rmax, zmin, zmax]` of the segments.
    pub bbox: [f64; 4],
}

/// The size field with the geometry of its fine regions resolved, ready to evaluate.
#[derive(Debug, Clone)]
pub(crate) struct ResolvedSizeField {
    pub field: SizeField,
    pub fine: Vec<FineRegion>,
}

impl ResolvedSizeField {
    /// h(x) for a point in the region `tag` (see the module docs).
    pub fn at(&self, x: [f64; 2], tag: Option<u32>) -> f64 {
        let mut h = match tag {
            Some(t) => self.field.region_target(t),
            None => self.field.max_edge_m,
        };
        let g = self.field.growth;
        for region in &self.fine {
            if region.edge_m >= h {
                continue;
            }
            // Cheap lower bound on the distance first: the distance to the bounding box.
            let dr = (region.bbox[0] - x[0]).max(x[0] - region.bbox[1]).max(0.0);
            let dz = (region.bbox[2] - x[1]).max(x[1] - region.bbox[3]).max(0.0);
            if region.edge_m + g * (dr * dr + dz * dz).sqrt() >= h {
                continue;
            }
            let mut d2 = f64::INFINITY;
            for s in &region.segments {
                d2 = d2.min(point_segment_distance2(x, s[0], s[1]));
            }
            h = h.min(region.edge_m + g * d2.sqrt());
        }
        h
    }
}

/// Squared distance from point x to the segment pq.
pub(crate) fn point_segment_distance2(x: [f64; 2], p: [f64; 2], q: [f64; 2]) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1]];
    let w = [x[0] - p[0], x[1] - p[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 { ((w[0] * d[0] + w[1] * d[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
    let e = [w[0] - t * d[0], w[1] - t * d[1]];
    e[0] * e[0] + e[1] * e[1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_grows_linearly_away_from_a_fine_region() {
        let field = SizeField::uniform(1.0).with_region(5, 0.01);
        let resolved = ResolvedSizeField {
            field,
            fine: vec![FineRegion {
                edge_m: 0.01,
                segments: vec![[[0.0, 0.0], [0.0, 1.0]]],
                bbox: [0.0, 0.0, 0.0, 1.0],
            }],
        };
        assert!((resolved.at([0.5, 0.5], None) - (0.01 + 0.3 * 0.5)).abs() < 1e-12);
        assert!((resolved.at([0.5, 0.5], Some(5)) - 0.01).abs() < 1e-12);
        assert!((resolved.at([10.0, 0.5], None) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn invalid_fields_are_rejected() {
        assert!(SizeField::uniform(0.0).validate().is_err());
        assert!(SizeField::uniform(1.0).with_region(1, -1.0).validate().is_err());
        assert!(SizeField { growth: 0.0, ..SizeField::uniform(1.0) }.validate().is_err());
    }
}
