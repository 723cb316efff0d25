//! Rendering to an abstract dot canvas (no terminal dependency): camera, depth-buffered
//! rasterizer, and conversion to braille, ASCII or half-block cells, SVG and PNG.
