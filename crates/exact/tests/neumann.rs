use signorini_exact::*;
#[test]
fn explore() {
    let s = BarNeumannGravity::periodic(40.0).unwrap();
    println!("{:?}", s.events());
    println!("{:?}", s.breakpoints().collect::<Vec<_>>());
    let s = BarNeumannGravity::paper(40.0).unwrap();
    println!("{:?}", s.events());
    println!("{:?}", s.breakpoints().collect::<Vec<_>>());
    let s = BarNeumannGravity::new(1e-3, 1.0, 1.0, 20.0).unwrap();
    println!("{:?}", s.events());
    println!("{:?}", s.breakpoints().count());
}
