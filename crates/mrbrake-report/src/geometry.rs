//! The report of a brake geometry exported for Gmsh (`mrbrake_design::geometry`,
//! `mrbrake_design::geo_export`): the regions, fluid gaps and coils with their physical tags.

use std::path::Path;

use mrbrake_design::geometry::BrakeGeometry;
use serde_json::{Value, json};

/// The JSON report of `geometry` written to `output` for the spec `spec_name`: the boundary
/// tags, every region, gap and coil (units counted from 1), and the spec's `warnings`.
pub fn export_json(
    geometry: &BrakeGeometry,
    spec_name: &str,
    output: &Path,
    warnings: &[String],
) -> Value {
    let regions: Vec<_> = geometry
        .regions
        .iter()
        .map(|r| json!({ "tag": r.tag, "name": r.name, "material": r.material, "area_m2": r.area_m2() }))
        .collect();
    let gaps: Vec<_> = geometry
        .gaps
        .iter()
        .map(|g| {
            json!({
                "index": g.index + 1, "unit": g.unit + 1, "index_in_unit": g.index_in_unit + 1, "tag": g.tag,
                "r_m": g.shear_radius_m, "height_m": g.height_m, "width_m": g.width_m,
                "inner_wall_tag": g.inner_wall_tag, "outer_wall_tag": g.outer_wall_tag,
            })
        })
        .collect();
    let coils: Vec<_> = geometry
        .coils
        .iter()
        .map(|c| json!({ "tag": c.tag, "unit": c.unit + 1, "turns": c.turns, "current_sign": c.current_sign }))
        .collect();
    json!({
        "output": output.display().to_string(),
        "spec": spec_name,
        "axis_tag": geometry.axis_tag,
        "outer_tag": geometry.outer_tag,
        "regions": regions,
        "gaps": gaps,
        "coils": coils,
        "warnings": warnings,
    })
}

/// The line reporting the `.geo` file written to `output` and how to mesh it.
pub fn export_text(geometry: &BrakeGeometry, output: &Path) -> String {
    format!(
        "wrote {} ({} regions, {} fluid gaps, {} coils; mesh it with: gmsh -2 {})\n",
        output.display(),
        geometry.regions.len(),
        geometry.gaps.len(),
        geometry.coils.len(),
        output.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_design::geometry::build;
    use mrbrake_design::spec::default_spec;

    #[test]
    fn the_export_report_lists_every_part_with_units_from_one() {
        let geometry = build(&default_spec()).unwrap();
        let out = Path::new("brake.geo");
        let text = export_text(&geometry, out);
        assert!(text.starts_with("wrote brake.geo ("), "{text}");
        assert!(
            text.contains(" 8 fluid gaps, 2 coils; mesh it with: gmsh -2 brake.geo)"),
            "{text}"
        );
        let json = export_json(&geometry, "thesis", out, &["a warning".into()]);
        assert_eq!(json["regions"].as_array().unwrap().len(), geometry.regions.len());
        let units: Vec<u64> =
            json["gaps"].as_array().unwrap().iter().map(|g| g["unit"].as_u64().unwrap()).collect();
        assert_eq!(units, [1, 1, 1, 1, 2, 2, 2, 2]);
        assert_eq!(json["warnings"][0], "a warning");
    }
}
