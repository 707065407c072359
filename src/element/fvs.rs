//! The reduced Fraeijs de Veubeke–Sanders quadrilateral (in progress).
