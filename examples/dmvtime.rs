use geocert::diamond::*;
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = &args[1];
    let side: usize = args[2].parse().unwrap();
    let t = Instant::now();
    let f = builtin_volume(name, side).unwrap();
    println!("volume {:.2}s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let dmv = FullDmv::build(f);
    println!("build {:.2}s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let sel = dmv.select_by_error(0.0);
    println!("select err0 {:.2}s np={} nf={}", t.elapsed().as_secs_f64(), sel.count(), dmv.len());
    let ds = dmv.supercube_encoding(&sel);
    let dd = dmv.diamond_encoding(&sel);
    println!("ns={} conc={:.1}", ds.supercubes(), sel.count() as f64 / ds.supercubes() as f64);
    let lod = Lod { error: Some(2.0), isovalues: vec![100.0], ..Lod::default() };
    for enc in 0..3 {
        let t = Instant::now();
        let (v, n, b) = match enc {
            0 => { let mut r: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dmv); r.refine(&lod).unwrap(); let el = t.elapsed(); (r.visited, el.as_nanos() as usize, r.front.bookkeeping_bytes()) }
            1 => { let mut r: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dd); r.refine(&lod).unwrap(); let el = t.elapsed(); (r.visited, el.as_nanos() as usize, r.front.bookkeeping_bytes()) }
            _ => { let mut r: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&ds); r.refine(&lod).unwrap(); let el = t.elapsed(); (r.visited, el.as_nanos() as usize, r.front.bookkeeping_bytes()) }
        };
        let s = n as f64 * 1e-9;
        println!("enc {enc}: visited {v} in {s:.3}s = {:.2} M/s, {b} bytes", v as f64 / s / 1e6);
    }
}
