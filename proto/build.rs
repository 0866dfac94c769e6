//! Compiles `trackd.proto` with protox (pure Rust; no `protoc` binary needed) and generates
//! the prost types.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("cargo:rerun-if-changed=trackd.proto");
    let descriptors = protox::compile(["trackd.proto"], ["."])?;
    prost_build::Config::new().compile_fds(descriptors)?;
    Ok(())
}
