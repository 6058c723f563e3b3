//! The reports' style sheet, inlined in every page: readable on screen at 100 % zoom and printed
//! on A4 (figures and tables kept whole, no navigation, black text on white).

/// The style sheet.
pub const CSS: &str = r#"
:root { color-scheme: light; }
body { font-family: "DejaVu Sans", "Liberation Sans", Helvetica, Arial, sans-serif; font-size: 15px;
  line-height: 1.45; color: #1a1a1a; background: #fff; margin: 0 auto; max-width: 1100px; padding: 0 24px 48px; }
header { border-bottom: 2px solid #0072b2; margin-bottom: 16px; }
h1 { font-size: 26px; margin: 24px 0 6px; }
h2 { font-size: 20px; margin: 32px 0 10px; border-bottom: 1px solid #ccc; padding-bottom: 3px; }
h3 { font-size: 16px; margin: 20px 0 8px; }
p.facts { margin: 2px 0; color: #444; }
nav ol { columns: 2; margin: 10px 0 16px; padding-left: 22px; }
a { color: #0060a0; }
table { border-collapse: collapse; margin: 8px 0 16px; font-size: 14px; }
caption { text-align: left; font-weight: bold; padding: 4px 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; vertical-align: top; text-align: left; }
thead th { background: #eef3f8; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
tbody tr:nth-child(even) { background: #fafafa; }
figure { margin: 12px 0 20px; }
.figure { display: block; max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 13px; color: #444; margin-top: 4px; }
pre { background: #f6f6f6; border: 1px solid #ddd; padding: 8px; font-size: 12.5px; overflow-x: auto;
  white-space: pre-wrap; }
.note { color: #444; font-size: 14px; }
.swatch { display: inline-block; width: 12px; height: 12px; border: 1px solid #555; margin-right: 6px;
  vertical-align: -1px; }
footer { margin-top: 40px; font-size: 12px; color: #666; border-top: 1px solid #ccc; padding-top: 6px; }
@page { size: A4; margin: 14mm 12mm; }
@media print {
  body { font-size: 10.5pt; max-width: none; padding: 0; }
  nav { display: none; }
  h2 { break-after: avoid; page-break-after: avoid; }
  figure, table, pre { break-inside: avoid; page-break-inside: avoid; }
  .figure { max-height: 240mm; width: auto; border: none; }
  section { break-before: auto; }
  a { color: inherit; text-decoration: none; }
  * { -webkit-print-color-adjust: exact; print-color-adjust: exact; }
}
"#;
