//! Image textures: texel tables (in flash on a chip) sampled at a surface's uv.
