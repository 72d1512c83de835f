//! FMI 2.0 layer.
