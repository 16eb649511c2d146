"""What people look at, all from one drawing of a mechanism: `drawing` (geometry and the
Matplotlib artists), `figures` (the CLI's plots and movies), `export` (SVG, DXF,
DataFrames), `page` (the interactive HTML page), `notebook` (rich display, `draw`,
`animate`), `targets` (a design's precision points in those pictures). Reads models and
results through their public API."""
