use rug::Float;

use super::*;

/// A small deterministic generator (xorshift64*).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
}

#[test]
fn equal_values_are_equal_decimals() {
    let forms = ["1.3", "1.30", "13e-1", "+0.13E1", "0001.300", "130e-2"];
    let first = Decimal::parse(forms[0]).unwrap();
    for f in forms {
        let d = Decimal::parse(f).unwrap();
        assert_eq!(d, first, "{f}");
        assert_eq!(d.as_str(), f, "the text as written is kept");
    }
    assert_ne!(
        Decimal::parse("1.3").unwrap(),
        Decimal::parse("1.31").unwrap()
    );
    assert_ne!(
        Decimal::parse("1.3").unwrap(),
        Decimal::parse("-1.3").unwrap()
    );
    assert_eq!(
        Decimal::parse("-0").unwrap(),
        Decimal::parse("0.000").unwrap()
    );
}

#[test]
fn what_is_not_a_finite_decimal_is_refused() {
    for bad in [
        "", " ", "nan", "NaN", "inf", "-inf", "infinity", "1e999", "-2e308", "0x10", "1.2.3", "e5",
        ".", "1e", "1e+", "--1", "1_000", "1,5", "١", "1e-99999",
    ] {
        assert!(Decimal::parse(bad).is_err(), "{bad:?} accepted");
    }
    assert!(matches!(
        Decimal::parse("inf"),
        Err(NumberError::NotFinite(_))
    ));
    assert!(matches!(
        Decimal::parse("1e999"),
        Err(NumberError::NotFinite(_))
    ));
    let long = "1".repeat(MAX_DECIMAL_CHARS + 1);
    assert!(matches!(
        Decimal::parse(&long),
        Err(NumberError::TooLong(_))
    ));
    // A message never repeats a long value.
    let junk = format!("{}x", "9".repeat(5000));
    let msg = Decimal::parse(&junk).unwrap_err().to_string();
    assert!(msg.len() < 120, "{msg}");
    // Extremes that are finite are fine.
    for good in [
        "1.7976931348623157e308",
        "5e-324",
        "1e-400",
        "0e99999999999999999999",
        ".5",
        "5.",
    ] {
        assert!(Decimal::parse(good).is_ok(), "{good:?} refused");
    }
}

#[test]
fn to_f64_rounds_like_the_standard_library() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..20_000 {
        let digits = 1 + (rng.next() % 30) as usize;
        let mantissa: String = (0..digits)
            .map(|_| char::from(b'0' + (rng.next() % 10) as u8))
            .collect();
        let exp = (rng.next() % 80) as i64 - 40;
        let text = format!("{mantissa}e{exp}");
        let d = Decimal::parse(&text).unwrap();
        assert_eq!(
            d.to_f64().to_bits(),
            text.parse::<f64>().unwrap().to_bits(),
            "{text}"
        );
    }
}

#[test]
fn to_float_is_within_half_an_ulp_of_the_decimal() {
    // 1/10 and 13/10 checked against their defining equations at a higher precision.
    for (text, num, den) in [("0.1", 1u32, 10u32), ("1.3", 13, 10), ("-0.52", 52, 100)] {
        let d = Decimal::parse(text).unwrap();
        for bits in [53u32, 64, 113, 200, 1000] {
            let x = d.to_float(bits);
            assert_eq!(x.prec(), bits);
            let wide = 2 * bits + 64;
            let sign = if d.is_negative() { -1 } else { 1 };
            // |x·den − sign·num| ≤ ulp(x)/2 · den
            let err =
                (Float::with_val(wide, &x * den) - Float::with_val(wide, sign * num as i32)).abs();
            let ulp = Float::with_val(wide, 1) << (x.get_exp().unwrap() - bits as i32);
            assert!(
                err <= Float::with_val(wide, &ulp * den) / 2u32,
                "{text} at {bits} bits"
            );
        }
    }
}

#[test]
fn a_binary64_value_is_written_out_exactly() {
    let tenth = Decimal::from_f64(0.1).unwrap();
    assert_eq!(
        tenth.as_str(),
        "0.1000000000000000055511151231257827021181583404541015625"
    );
    assert!(tenth.is_binary64());
    assert!(!Decimal::parse("0.1").unwrap().is_binary64());
    let mut rng = Rng(42);
    let mut values: Vec<f64> = vec![
        0.0,
        -0.0,
        5e-324,
        -5e-324,
        f64::MAX,
        f64::MIN_POSITIVE,
        1.0,
        3.0,
        1e22,
        1e23,
    ];
    for _ in 0..3000 {
        let x = f64::from_bits(rng.next());
        if x.is_finite() {
            values.push(x);
        }
    }
    for x in values {
        let d = Decimal::from_f64(x).unwrap();
        assert_eq!(
            d.to_f64().to_bits(),
            if x == 0.0 {
                0.0f64.to_bits()
            } else {
                x.to_bits()
            },
            "{x:e}"
        );
        // The exact value: at 1200 bits (more than any f64 needs) the decimal is x itself.
        assert_eq!(d.to_float(1200), Float::with_val(53, x), "{x:e}");
        assert!(d.is_binary64(), "{x:e}");
    }
    assert!(Decimal::from_f64(f64::NAN).is_err());
    assert!(Decimal::from_f64(f64::INFINITY).is_err());
}

#[test]
fn the_shortest_decimal_of_an_f64_is_its_debug_text() {
    for x in [0.3, 1.3, -0.52, 2.07, 1e300, 1e-7, 100.0] {
        let d = Decimal::shortest(x).unwrap();
        assert_eq!(d.to_f64(), x);
        assert_eq!(d, Decimal::parse(&format!("{x}")).unwrap());
    }
}

/// k·T/(N−1) rounded once, checked against the same quotient at four times the precision.
#[test]
fn grid_times_are_correctly_rounded() {
    let mut rng = Rng(7);
    let mut naive_differs = 0;
    for t_text in [
        "100",
        "0.3",
        "1.1",
        "50",
        "7.000000000000000000000000000001",
        "1e-3",
        "123.456",
    ] {
        let t = Decimal::parse(t_text).unwrap();
        for samples in [2usize, 3, 11, 201, 1001] {
            let times = Times::grid(t.clone(), samples);
            assert_eq!(times.time_f64(0), 0.0);
            assert_eq!(times.time_f64(samples - 1), t.to_f64());
            for _ in 0..20 {
                let k = (rng.next() as usize) % samples;
                for bits in [53u32, 120, 400] {
                    let got = times.time(k, bits);
                    let wide = 4 * bits + 200;
                    let exact =
                        Float::with_val(wide, t.to_float(wide) * k as u32) / ((samples - 1) as u32);
                    let want = Float::with_val(bits, &exact);
                    assert_eq!(
                        got, want,
                        "T = {t_text}, N = {samples}, k = {k}, {bits} bits"
                    );
                }
                let naive = t.to_f64() * k as f64 / (samples - 1) as f64;
                if naive != times.time_f64(k) {
                    naive_differs += 1;
                }
            }
        }
    }
    // The check can fail: rounding T to f64 first gives other times.
    assert!(naive_differs > 0);
    // Integer T (the documented grids): the same times as the f64 grid of before.
    let grid = Times::grid(Decimal::parse("100").unwrap(), 1001);
    for k in 0..1001 {
        assert_eq!(grid.time_f64(k), 100.0 * k as f64 / 1000.0);
    }
}

#[test]
fn serde_writes_numbers_and_reads_strings_exactly() {
    let d = Decimal::parse("1.3").unwrap();
    assert_eq!(serde_json::to_string(&d).unwrap(), "1.3");
    let long: Decimal = serde_json::from_str("\"1.30000000000000004440892098500626162\"").unwrap();
    assert_eq!(long.as_str(), "1.30000000000000004440892098500626162");
    let short: Decimal = serde_json::from_str("1.3").unwrap();
    assert_eq!(short, d);
    let int: Decimal = serde_json::from_str("-7").unwrap();
    assert_eq!(int, Decimal::from_integer(-7));
    assert!(serde_json::from_str::<Decimal>("\"nan\"").is_err());
}
