//! The Argyris triangle (in progress).
