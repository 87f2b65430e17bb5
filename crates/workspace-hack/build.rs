//! Empty: it exists so that cargo resolves the build dependencies (the `syn` feature set).

fn main() {}
