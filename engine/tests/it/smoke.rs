use crate::common;
use common::*;

#[test]
fn loop_sums() {
    let src = "#1=0\n#2=0\nWHILE[#1LT10]DO1\n#2=#2+#1\n#1=#1+1\nEND1\n#100=#2\nM30\n";
    assert_eq!(var(src, 100), Some(45.0));
}

#[test]
fn motion_positions() {
    let r = run_src("G90 G54 G00 X10 Y20.\nG01 Z-5. F100\n#100=#5001\n#101=#5002\n#102=#5003\nM30\n");
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.variables, vec![(100, 0.01), (101, 20.0), (102, -5.0)]);
}
