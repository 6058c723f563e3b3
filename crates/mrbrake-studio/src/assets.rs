//! The page: plain HTML, CSS and JavaScript in `assets/`, embedded in the binary (no build step,
//! no package from a registry, nothing fetched from elsewhere: the policy below forbids it).

/// The page's script.
pub const SCRIPT: &str = include_str!("../assets/studio.js");
/// The page's style sheet.
pub const STYLE: &str = include_str!("../assets/studio.css");
/// The page, with `{{TOKEN}}` where the token goes (its script and style sheet are requested
/// with it).
const PAGE: &str = include_str!("../assets/index.html");

/// What the page may load and run: its own script, style sheet and API only (inline styles for
/// the renderers' SVG attributes, `data:` images for the field map's raster).
pub const CSP: &str = "default-src 'none'; script-src 'self'; style-src 'self' 'unsafe-inline'; \
     img-src 'self' data:; connect-src 'self'; base-uri 'none'; form-action 'none'; \
     frame-ancestors 'none'";

/// The page for a client holding `token` (hex digits only, so nothing to escape).
pub fn page(token: &str) -> String {
    PAGE.replace("{{TOKEN}}", token)
}
