//! tmp
#[test]
fn tmp() {
    for p in [
        geocert::internals::proofs::diamond::supercube,
        geocert::internals::proofs::diamond::implicit_vs_explicit,
    ] {
        let o = p();
        println!("{}", o.summary());
        for f in &o.failures {
            println!("  {f}");
        }
        assert!(o.ok());
    }
}
