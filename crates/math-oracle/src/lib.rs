//! Nothing here: the package is its tests (`tests/`), which check `mazewalk-math` against
//! nalgebra and cgmath.
