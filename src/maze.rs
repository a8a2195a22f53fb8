//! maze (to be written).
