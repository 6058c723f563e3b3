//! The coloured triangles of a map as one image: every pixel takes the colour of the triangle its
//! centre lies in. Drawn as a bitmap, neighbouring triangles meet without the hairline seams that
//! anti-aliased SVG polygons leave when a viewer rasterises them, and a map of tens of thousands of
//! triangles stays a small file. In an SVG the image is an inline PNG (`<image>`), the flux lines,
//! outlines and text stay vectors.

use plotters::style::RGBColor;

use super::lines::Window;
use crate::ReportError;

/// Pixels of `window` (m) at `size` (width, height): RGB rows from the top, white where no
/// triangle lies; triangle `t` has the colour `colour(t)`.
pub fn rasterise(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    colour: &dyn Fn(usize) -> RGBColor,
    window: Window,
    size: (u32, u32),
) -> Vec<u8> {
    let (w, h) = (size.0 as usize, size.1 as usize);
    let mut rgb = vec![255u8; 3 * w * h];
    let (lo, hi) = window;
    let (sx, sy) = (w as f64 / (hi[0] - lo[0]), h as f64 / (hi[1] - lo[1]));
    // Pixel coordinates of a point: x to the right, y down from the window's top.
    let px = |v: usize| ((nodes[v][0] - lo[0]) * sx, (hi[1] - nodes[v][1]) * sy);
    for (t, tri) in triangles.iter().enumerate() {
        let p = [px(tri[0]), px(tri[1]), px(tri[2])];
        let x0 = p.iter().map(|q| q.0).fold(f64::INFINITY, f64::min).floor().max(0.0) as usize;
        let x1 = p.iter().map(|q| q.0).fold(f64::NEG_INFINITY, f64::max).ceil().min(w as f64);
        let y0 = p.iter().map(|q| q.1).fold(f64::INFINITY, f64::min).floor().max(0.0) as usize;
        let y1 = p.iter().map(|q| q.1).fold(f64::NEG_INFINITY, f64::max).ceil().min(h as f64);
        if x1 <= 0.0 || y1 <= 0.0 {
            continue;
        }
        let area = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[2].0 - p[0].0) * (p[1].1 - p[0].1);
        if area.abs() < 1e-12 {
            continue;
        }
        let c = colour(t);
        for y in y0..y1 as usize {
            for x in x0..x1 as usize {
                if covers(&p, area, (x as f64 + 0.5, y as f64 + 0.5)) {
                    let k = 3 * (y * w + x);
                    rgb[k..k + 3].copy_from_slice(&[c.0, c.1, c.2]);
                }
            }
        }
    }
    rgb
}

/// Whether the triangle `p` (signed doubled area `area`) covers the point `q`, edges included
/// (a pixel centre on a shared edge takes either triangle's colour, never none).
fn covers(p: &[(f64, f64); 3], area: f64, q: (f64, f64)) -> bool {
    let edge = |a: (f64, f64), b: (f64, f64)| (b.0 - a.0) * (q.1 - a.1) - (q.0 - a.0) * (b.1 - a.1);
    let tolerance = -1e-9 * area.abs();
    let s = area.signum();
    [edge(p[0], p[1]), edge(p[1], p[2]), edge(p[2], p[0])].iter().all(|&e| e * s >= tolerance)
}

/// `rgb` (8-bit RGB rows of `size`) as a PNG file.
pub fn encode_png(rgb: &[u8], size: (u32, u32)) -> Result<Vec<u8>, ReportError> {
    let backend = |e: png::EncodingError| ReportError::Backend(format!("PNG encoding: {e}"));
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, size.0, size.1);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Best);
    let mut writer = encoder.write_header().map_err(backend)?;
    writer.write_image_data(rgb).map_err(backend)?;
    writer.finish().map_err(backend)?;
    Ok(out)
}

/// An image to put into an SVG document: its place `(x, y, width, height)` in the document's
/// pixels and its PNG bytes (of any resolution: a viewer scales it to the place).
#[derive(Debug, Clone)]
pub struct SvgImage {
    /// Left, top, width and height in the SVG's pixels.
    pub place: (i32, i32, u32, u32),
    /// The PNG file.
    pub png: Vec<u8>,
}

/// `svg` with `image` inserted right after the background (the first `<rect .../>`), so that
/// everything plotters drew (lines, outlines, text) lies over it.
pub fn splice(svg: &str, image: &SvgImage) -> String {
    let (x, y, w, h) = image.place;
    let element = format!(
        "<image x=\"{x}\" y=\"{y}\" width=\"{w}\" height=\"{h}\" preserveAspectRatio=\"none\" \
         style=\"image-rendering:pixelated\" href=\"data:image/png;base64,{}\"/>\n",
        crate::html::base64(&image.png)
    );
    let after_background = svg
        .find("<rect")
        .and_then(|start| svg[start..].find("/>").map(|end| start + end + 2))
        .or_else(|| svg.find("<svg").and_then(|s| svg[s..].find('>').map(|e| s + e + 1)));
    match after_background {
        Some(at) => {
            let at = if svg[at..].starts_with('\n') { at + 1 } else { at };
            format!("{}{element}{}", &svg[..at], &svg[at..])
        }
        None => format!("{svg}{element}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles that tile a square leave no pixel of it white (no seam on the diagonal).
    #[test]
    fn two_triangles_tile_a_square_without_a_seam() {
        let nodes = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        let red = |t: usize| if t == 0 { RGBColor(200, 0, 0) } else { RGBColor(0, 0, 200) };
        let rgb = rasterise(&nodes, &triangles, &red, ([0.0, 0.0], [1.0, 1.0]), (37, 23));
        assert!(rgb.chunks(3).all(|p| p != [255, 255, 255]), "a white pixel");
        // The lower right corner is the first triangle's, the upper left the second's.
        assert_eq!(&rgb[3 * (22 * 37 + 36)..][..3], &[200, 0, 0]);
        assert_eq!(&rgb[..3], &[0, 0, 200]);
    }

    #[test]
    fn the_image_goes_after_the_background() {
        let svg = "<svg width=\"10\" height=\"10\">\n<rect x=\"0\" y=\"0\" fill=\"#FFFFFF\"/>\n<text>a</text>\n</svg>";
        let image = SvgImage { place: (1, 2, 3, 4), png: vec![1, 2, 3] };
        let out = splice(svg, &image);
        let (background, image_at, text) =
            (out.find("<rect").unwrap(), out.find("<image").unwrap(), out.find("<text").unwrap());
        assert!(background < image_at && image_at < text, "{out}");
        assert!(out.contains("x=\"1\" y=\"2\" width=\"3\" height=\"4\""));
        assert!(out.contains("data:image/png;base64,AQID"));
    }
}
