//! Delimited text tables as rigs export them (CSV, TXT, DAT, TSV), dialect found from the file.
//!
//! What is sniffed from the first lines: a UTF-8 byte-order mark, CRLF or LF line ends, the
//! delimiter (tab, semicolon, comma or runs of whitespace), decimal commas, the header line
//! below any preamble (the last line above the first run of numeric rows that has as many
//! fields), and a trailing delimiter on every line. Lines after the data that are not data
//! (an `End of data` or a summary) are the footer: reported, not an error. A file of numbers
//! only (a DAQ or microcontroller log; comment lines of one field may stand above) has no
//! header: its columns are named `#1`, `#2`, … by position ([`crate::table::Table::headerless`]).
//! Double quotes protect a delimiter inside a field, in the header and in the data (a quoted
//! `"1,5"` in a comma-delimited file is a decimal comma); header bytes that are not UTF-8 are
//! Latin-1. A non-numeric cell
//! inside the data only matters when a role is mapped to its column
//! ([`crate::table::ColumnData::NotNumeric`]).
//!
//! The data lines are parsed in parallel chunks (rayon) straight from the memory-mapped file
//! into the final columns: plain decimals exactly by [`crate::decimal`], other numbers with
//! `fast-float2`. The result does not depend on the number of threads.
//!
//! The stages: [`options`] (the dialect's vocabulary), [`fields`] (lines, quoting, numbers),
//! [`sniff`] (dialect and header line), [`header`] (column names, units, the layout in
//! words), [`chunks`] (the data lines in parallel) and [`assemble`] (the whole file, its
//! blocks and footer, into a [`Table`](crate::table::Table)).

mod assemble;
mod chunks;
mod fields;
mod header;
mod options;
mod sniff;

pub use assemble::{parse_text_table, read_text_table};
pub use options::{Delimiter, TextOptions};

#[cfg(test)]
mod tests {
    use super::{assemble::*, fields::*, options::*};
    use crate::table::Table;
    use greybox_core::Result;

    fn parse(text: &str) -> Result<Table> {
        parse_text_table(text.as_bytes(), "t.csv", &TextOptions::default())
    }
    fn col(t: &Table, k: usize) -> &[f64] {
        t.columns[k].values(&t.source).unwrap()
    }

    #[test]
    fn plain_csv() {
        let t = parse("time_s,normal_force_N\n0,1.5\n0.001,2.5\n0.002,3\n").unwrap();
        assert_eq!(t.rows, 3);
        assert_eq!(col(&t, 1), &[1.5, 2.5, 3.0]);
        assert_eq!(t.columns[0].unit.as_deref(), Some("s"));
        assert_eq!(t.header_line, 1);
    }

    #[test]
    fn preamble_trailing_delimiter_footer() {
        let text = "Instrument: RT,Serial 12\nTest: 2026-05-03 10:12,Operator: X\n\
                    Step, Time (s), DAQ.Fz (N), DAQ.Fx (N),\n1,0.0,10.0,4.0,\n1,0.1,10.1,4.1,\n\
                    2,0.0,10.2,4.2,\n2,0.1,10.3,4.3,\nEnd of data,\nTotal time: 250 s\n";
        let t = parse(text).unwrap();
        assert_eq!(t.header_line, 3);
        assert_eq!(t.columns.len(), 4);
        assert_eq!(t.columns[2].name, "DAQ.Fz");
        assert_eq!(col(&t, 3), &[4.0, 4.1, 4.2, 4.3]);
        assert_eq!(t.preamble.len(), 2);
        assert_eq!(t.footer.len(), 2);
        assert_eq!(t.footer[0].0, 8);
        assert!(t.layout.contains("trailing delimiter"), "{}", t.layout);
    }

    #[test]
    fn semicolon_decimal_comma_bom_crlf() {
        let text = "\u{feff}Zeit [s];Fn [kN];Ft/N\r\n0,000;0,2001;80,5\r\n0,002;0,2002;80,6\r\n0,004;0,2003;80,7\r\n";
        let t = parse(text).unwrap();
        assert_eq!(col(&t, 1), &[0.2001, 0.2002, 0.2003]);
        assert_eq!(col(&t, 2), &[80.5, 80.6, 80.7]);
        assert!(t.layout.contains("decimal comma") && t.layout.contains("BOM"));
        assert_eq!(t.columns[0].name, "Zeit");
    }

    #[test]
    fn tab_and_whitespace() {
        let t = parse("Fz_kN\tFx_N\tSpeed_mm/s\n0.4\t160\t500\n0.4\t161\t500\n0.4\t162\t501\n")
            .unwrap();
        assert_eq!(t.columns[2].unit.as_deref(), Some("mm/s"));
        assert_eq!(col(&t, 1), &[160.0, 161.0, 162.0]);
        let t = parse("Time  Normal force  Friction force\n0   10  4\n0.1 10  4.1\n0.2 10  4.2\n")
            .unwrap();
        assert_eq!(t.columns.len(), 3);
        assert_eq!(t.columns[1].name, "Normal force");
    }

    #[test]
    fn text_column_only_fails_when_used() {
        let t = parse("t_s,F_N,comment\n0,1,ok\n1,2,fine\n2,3,x\n").unwrap();
        assert_eq!(col(&t, 1), &[1.0, 2.0, 3.0]);
        let e = t.columns[2].values(&t.source).unwrap_err().to_string();
        assert!(
            e.contains("line 2") && e.contains("comment") && e.contains("'ok'"),
            "{e}"
        );
    }

    #[test]
    fn broken_rows_are_errors_with_lines() {
        let e = parse("t_s,F_N\n0,1\n1,2\n2\n3,4\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 4") && e.contains("expected 2 fields, found 1"),
            "{e}"
        );
        let e = parse("t_s,F_N\n0,1\n1,2\nsomething else here\n3,4\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("not data"), "{e}");
        let t = parse("t_s,F_N,G_N\n0,1,1\n1,abc,2\n2,3,3\n").unwrap();
        let e = t.columns[1].values(&t.source).unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("'abc'"), "{e}");
        let e = parse("just some text\nno numbers\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no table found"), "{e}");
        // numbers only are a headerless table (see `headerless_logs`), but numbers and
        // broken rows above the data are not
        let e = parse("t_s,F_N\n0,1\n1,abc\n2,3\n").unwrap_err().to_string();
        assert!(
            e.contains("line 4") && e.contains("not a header that names them"),
            "{e}"
        );
        // a header line that names fewer columns than the data has is not taken as comments
        let e = parse("time,force\n0,1,2\n1,2,3\n2,3,4\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("3 columns"), "{e}");
    }

    /// DAQ and microcontroller logs without a header: comma, semicolon with decimal comma,
    /// tab and whitespace, with comment lines above; columns are `#1`, `#2`, …
    #[test]
    fn headerless_logs() {
        let cases = [
            ("0.00,12.1,3.4\n0.01,12.0,3.5\n0.02,12.2,3.6\n", "comma"),
            (
                "0,00;12,1;3,4\r\n0,01;12,0;3,5\r\n0,02;12,2;3,6\r\n",
                "semicolon",
            ),
            (
                "# logger v2\n\n0.00\t12.1\t3.4\n0.01\t12.0\t3.5\n0.02\t12.2\t3.6\n",
                "tab",
            ),
            (
                "  0.00  12.1  3.4\n  0.01  12.0  3.5\n  0.02  12.2  3.6\n",
                "whitespace",
            ),
        ];
        for (text, delim) in cases {
            let t = parse(text).unwrap();
            assert!(t.headerless, "{delim}");
            let names: Vec<&str> = t.columns.iter().map(|c| c.name.as_str()).collect();
            assert_eq!(names, ["#1", "#2", "#3"], "{delim}");
            assert_eq!(col(&t, 0), &[0.0, 0.01, 0.02], "{delim}");
            assert_eq!(col(&t, 2), &[3.4, 3.5, 3.6], "{delim}");
            assert!(t.layout.starts_with(delim), "{}", t.layout);
            assert!(
                t.layout.contains("no header line (columns #1 to #3)"),
                "{}",
                t.layout
            );
            // the "header" is the line above the data, so header + 1 + row is the row's line
            assert_eq!(t.header_line + 1, if delim == "tab" { 3 } else { 1 });
        }
        let t = parse("# logger v2\n0.00\t12.1\t3.4\n0.01\t12.0\t3.5\n").unwrap();
        assert_eq!(t.preamble, ["# logger v2"]);
        // a malformed row names the line and that there is no header
        let e = parse("1,2\n3,4\n5\n6,7\n").unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("no header line"), "{e}");
    }

    /// A log of one column (only the rig's μ, one number per line) is a table of one column,
    /// with or without a header and CRLF; numbers in a preamble above a table of several
    /// columns never become a one-column table.
    #[test]
    fn one_column_logs() {
        let t = parse("COF\r\n0.31\r\n0.32\r\n\r\n0.30\r\n").unwrap();
        assert_eq!(t.columns.len(), 1);
        assert_eq!(t.columns[0].name, "COF");
        assert_eq!(col(&t, 0), &[0.31, 0.32, 0.30]);
        assert!(t.layout.starts_with("one column"), "{}", t.layout);
        let t = parse("0.31\n0.32\n").unwrap();
        assert!(t.headerless && t.columns.len() == 1, "{}", t.layout);
        let t = parse("Serial\n12345\n67890\nTime,Fz,Fx\n0,1,2\n1,1,2\n2,1,2\n").unwrap();
        assert_eq!(t.columns.len(), 3, "{}", t.layout);
        assert_eq!(t.header_line, 4);
        // a single number below a header of several names is no one-column table
        assert!(parse("Time,Fz\n1\n2\n3\n").is_err());
    }

    /// A forced header line is taken even where sniffing would choose another layout, and a
    /// forced line that is no header is an error naming it, never ignored.
    #[test]
    fn forced_header_is_never_ignored() {
        let opts = |h| TextOptions {
            header_line: Some(h),
            ..Default::default()
        };
        let text = "Time,Fn,Ft\n0,1,2\n1,2,3\n2,3,4\n";
        let t = parse_text_table(text.as_bytes(), "t.csv", &opts(1)).unwrap();
        assert_eq!(t.header_line, 1);
        assert!(!t.headerless);
        assert_eq!(t.columns[2].name, "Ft");
        // a header of channel numbers, which sniffing takes for data, is the header when forced
        let t = parse_text_table(b"0,1,2\n1,2,3\n2,3,4\n", "t.csv", &opts(1)).unwrap();
        assert!(!t.headerless);
        assert_eq!(t.rows, 2);
        assert_eq!(t.columns[1].name, "1");
        assert_eq!(col(&t, 1), &[2.0, 3.0]);
        let t = parse_text_table(b"0,1,2\n1,2,3\n2,3,4\n", "t.csv", &TextOptions::default());
        assert!(t.unwrap().headerless);
        // a forced header naming another number of columns is an error naming its line
        let e = parse_text_table(b"a,b\n1,2,3\n2,3,4\n", "t.csv", &opts(1))
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1") && e.contains("names 2 columns"), "{e}");
    }

    /// Quotes protect delimiters in headers and in data fields; a quoted `"1,5"` in a
    /// comma-delimited file is a decimal comma.
    #[test]
    fn quoted_fields_with_delimiters() {
        let text = "\"Time, s\",\"Load, N\",\"Friction, N\"\n\"0,0\",\"10,5\",\"1,5\"\n\"0,1\",\"10,5\",\"1,25\"\n0.2,10.5,\"1,0\"\n";
        let t = parse(text).unwrap();
        assert_eq!(t.columns.len(), 3);
        assert_eq!(t.columns[1].header, "Load, N");
        assert_eq!(col(&t, 0), &[0.0, 0.1, 0.2]);
        assert_eq!(col(&t, 2), &[1.5, 1.25, 1.0]);
        // two commas in quotes are no number, nor a comma that may separate thousands
        for bad in ["\"1,234,5\"", "\"1,234\"", "\"-12,500\"", "\"999,000\""] {
            assert_eq!(parse_number(bad.as_bytes(), false), None, "{bad}");
        }
        for (good, v) in [
            ("\"0,125\"", 0.125),
            ("\"12,25\"", 12.25),
            ("\"1234,500\"", 1234.5),
        ] {
            assert_eq!(parse_number(good.as_bytes(), false), Some(v), "{good}");
        }
        // with the file's decimal comma, the same field is a decimal
        assert_eq!(parse_number(b"\"1,234\"", true), Some(1.234));
    }

    /// Header bytes that are not UTF-8 are Latin-1: `µm` written as 0xB5 keeps its unit.
    #[test]
    fn latin1_header() {
        let mut bytes = b"t (s);Pos (".to_vec();
        bytes.push(0xB5);
        bytes.extend_from_slice(b"m);Fz (N)\n0;1;2\n1;2;3\n2;3;4\n");
        let t = parse_text_table(&bytes, "t.csv", &TextOptions::default()).unwrap();
        assert_eq!(t.columns[1].unit.as_deref(), Some("µm"));
    }

    #[test]
    fn forced_header_line() {
        let text = "a,b\n1,2\nx_s,y_N\n0,1\n1,2\n2,3\n";
        let t = parse_text_table(
            text.as_bytes(),
            "t.csv",
            &TextOptions {
                header_line: Some(3),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(t.columns[0].name, "x");
        assert_eq!(t.rows, 3);
    }

    #[test]
    fn same_result_in_many_chunks() {
        let mut text = String::from("time_s,F_N\n");
        for i in 0..200_000 {
            text.push_str(&format!("{},{}\n", i as f64 * 1e-3, (i % 97) as f64 * 0.5));
        }
        let t = parse(&text).unwrap();
        assert_eq!(t.rows, 200_000);
        assert_eq!(col(&t, 1)[199_999], (199_999 % 97) as f64 * 0.5);
        assert!(t.footer.is_empty());
    }

    /// Tiny chunks, blank lines, rows only the general path reads (quoted, padded, exponent
    /// with a decimal comma) and a footer: every chunking gives the one-chunk table.
    #[test]
    fn chunk_boundaries_blank_lines_and_slow_rows() {
        let mut text = String::from("Messung 7\n\nt [s];Fz [N];Fx [N];\n");
        for i in 0..3_000 {
            let row = match i % 11 {
                0 => format!("\"{},{:03}\";\"{}\";1,5e2;\n", i / 1000, i % 1000, i % 7),
                3 => format!(" {},{:03} ; {} ;-0,25;\r\n", i / 1000, i % 1000, i % 5),
                5 => "\n".to_string(),
                _ => format!("{},{:03};{};{},5;\n", i / 1000, i % 1000, i % 13, i % 3),
            };
            text.push_str(&row);
        }
        text.push_str("Ende der Messung\n");
        let one =
            parse_in_chunks(text.as_bytes(), "t", &TextOptions::default(), usize::MAX).unwrap();
        assert_eq!(one.rows, 3_000 - 3_000 / 11 - 1);
        assert_eq!(one.footer.len(), 1);
        assert!(one.layout.contains("decimal comma"), "{}", one.layout);
        for min_chunk in [1, 7, 64, 1000] {
            let t =
                parse_in_chunks(text.as_bytes(), "t", &TextOptions::default(), min_chunk).unwrap();
            assert_eq!(t.rows, one.rows);
            assert_eq!(t.footer, one.footer);
            for k in 0..3 {
                assert_eq!(
                    col(&t, k),
                    col(&one, k),
                    "column {k}, chunks of {min_chunk} B"
                );
            }
        }
        assert_eq!(col(&one, 0)[0], 0.0);
        assert_eq!(col(&one, 2)[0], 150.0);
        assert_eq!(col(&one, 2)[3], -0.25);
        assert_eq!(col(&one, 1)[1], 1.0);
    }

    #[test]
    fn units_row_under_the_header() {
        let t = parse("Time,Fz,Fx,COF,Speed,Temp\ns,(N),gf,-,[mm/s],°C\n0,1,2,0.1,5,20\n1,1,2,0.1,5,20\n2,1,2,0.2,5,21\n")
            .unwrap();
        assert_eq!(t.rows, 3);
        let units: Vec<Option<&str>> = t.columns.iter().map(|c| c.unit.as_deref()).collect();
        assert_eq!(
            units,
            [
                Some("s"),
                Some("N"),
                Some("gf"),
                Some("-"),
                Some("mm/s"),
                Some("°C")
            ]
        );
        assert_eq!(t.header_line, 1);
        assert!(t.layout.contains("units row on line 2"), "{}", t.layout);
        // an empty unit, and a header that states its own unit, the same as the units row's
        let t = parse("Instrument X\n\nt;Fz (kN);Step\ns;kN;\n0;1;1\n1;2;1\n2;3;2\n").unwrap();
        assert_eq!(t.columns[0].unit.as_deref(), Some("s"));
        assert_eq!(t.columns[1].unit.as_deref(), Some("kN"));
        assert_eq!(t.columns[2].unit, None);
        assert_eq!(t.preamble, ["Instrument X"]);
        // a units row that contradicts the header is refused with both units and its line
        let e = parse("Instrument X\n\nt;Fz (kN);Step\ns;N;\n0;1;1\n1;2;1\n2;3;2\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 4") && e.contains("Fz") && e.contains("kN") && e.contains("says N"),
            "{e}"
        );
        // a text row of non-units above the data is the header, not units
        let t = parse("Instrument X,Serial 12\nTime,Force\n0,1\n1,2\n").unwrap();
        assert_eq!(t.columns[1].name, "Force");
        assert_eq!(t.preamble.len(), 1);
    }

    #[test]
    fn sparse_tab_rows_empty_names_and_duplicates() {
        let mut text = String::from("Test data\nt (s)\tF (N)\t\t\tF (N)\tLoad (N)\tv\n");
        for i in 0..5 {
            text.push_str(&format!(
                "{i}\t{}.5\t\t\t{}.5\t\t{}\t\t\n",
                i + 1,
                i + 1,
                2 * i
            ));
        }
        text.push_str("\nEnd of test\n");
        let t = parse(&text).unwrap();
        assert_eq!(t.rows, 5);
        // the two empty-named columns and the empty `Load` column are left out
        let names: Vec<&str> = t.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["t", "F", "F #2", "v"]);
        assert_eq!(t.columns[2].header, "F (N)");
        assert_eq!(t.positions, [1, 2, 5, 7]);
        assert_eq!(col(&t, 2), &[1.5, 2.5, 3.5, 4.5, 5.5]);
        assert_eq!(col(&t, 3), &[0.0, 2.0, 4.0, 6.0, 8.0]);
        assert_eq!(t.column_label(1), "column 2, the first of 2 with that name");
        assert_eq!(
            t.column_label(2),
            "column 5, the second of 2 with that name"
        );
        assert_eq!(t.column_label(3), "column 7");
        assert!(
            t.notes
                .iter()
                .any(|n| n.contains("column 3, column 4, Load (N)")),
            "{:?}",
            t.notes
        );
        assert_eq!(t.footer.len(), 1);
        // a column with some empty cells is kept and fails only when used
        let t = parse("a\tb\tc\n1\t2\t3\n2\t\t4\n3\t5\t6\n").unwrap();
        let e = t.columns[1].values(&t.source).unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("empty field"), "{e}");
        assert_eq!(col(&t, 2), &[3.0, 4.0, 6.0]);
    }

    fn blocks_text(blocks: usize, header2: &str) -> String {
        let mut text = String::from("Rig 7\nProfile: stepped\n");
        for b in 0..blocks {
            text.push_str(&format!(
                "\nStep {} started\nLoad setpoint,{}\n",
                b + 1,
                10 * (b + 1)
            ));
            text.push_str(if b == 1 { header2 } else { "Time,Fz,Fx" });
            text.push_str("\ns,N,N\n");
            for i in 0..4 {
                text.push_str(&format!("{i},{},{}.5\n", 10 * (b + 1), b * 10 + i));
            }
        }
        text.push_str("\nTest completed\n");
        text
    }

    #[test]
    fn blocks_with_settings_units_and_time_restarting() {
        for blocks in [2, 3] {
            let text = blocks_text(blocks, "Time,Fz,Fx");
            for min_chunk in [1, 16, usize::MAX] {
                let t =
                    parse_in_chunks(text.as_bytes(), "b.csv", &TextOptions::default(), min_chunk)
                        .unwrap();
                assert_eq!(t.rows, 4 * blocks);
                let starts: Vec<usize> = (0..blocks).map(|b| 4 * b).collect();
                assert_eq!(t.block_starts, starts);
                assert_eq!(t.block_preambles.len(), blocks);
                assert_eq!(t.block_preambles[1], ["Step 2 started", "Load setpoint,20"]);
                assert_eq!(t.block_preambles[0], t.preamble);
                assert_eq!(&col(&t, 0)[..5], &[0.0, 1.0, 2.0, 3.0, 0.0]);
                assert_eq!(col(&t, 1)[4 * blocks - 1], 10.0 * blocks as f64);
                assert_eq!(t.columns[1].unit.as_deref(), Some("N"));
                assert_eq!(t.footer.len(), 1);
                assert_eq!(t.block_of_row(5), 1);
                assert!(
                    t.layout.contains(&format!("{blocks} blocks")),
                    "{}",
                    t.layout
                );
            }
        }
        // a single table has no blocks
        let t = parse("Time,Fz\n0,1\n1,2\n").unwrap();
        assert!(t.block_starts.is_empty() && t.block_preambles.is_empty());
        assert_eq!(t.block_of_row(1), 0);
    }

    /// A block with a header but no data row keeps its place: the blocks after it keep their
    /// numbers (issue 46 item 5: an empty block renumbered the rest).
    #[test]
    fn an_empty_block_keeps_its_place() {
        let full = blocks_text(3, "Time,Fz,Fx");
        // block 2's rows removed: its settings and header stand right above block 3's
        let text: String = full
            .lines()
            .filter(|l| !(l.starts_with(|c: char| c.is_ascii_digit()) && l.contains(",20,")))
            .map(|l| format!("{l}\n"))
            .collect();
        for min_chunk in [1, 16, usize::MAX] {
            let t = parse_in_chunks(text.as_bytes(), "b.csv", &TextOptions::default(), min_chunk)
                .unwrap();
            assert_eq!(t.rows, 8);
            assert_eq!(t.block_starts, [0, 4, 4]);
            assert_eq!(t.block_preambles[1], ["Step 2 started", "Load setpoint,20"]);
            assert_eq!(t.block_preambles[2], ["Step 3 started", "Load setpoint,30"]);
            assert_eq!(t.block_of_row(4), 2);
        }
    }

    #[test]
    fn block_with_another_header_is_refused() {
        // same field count, other names
        let e = parse(&blocks_text(3, "Time,Fn,Ft"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 15") && e.contains("'Time, Fz, Fx'") && e.contains("'Time, Fn, Ft'"),
            "{e}"
        );
        // another field count: its rows are malformed, the header is named
        let e = parse(&blocks_text(2, "Time,Fz")).unwrap_err().to_string();
        assert!(e.contains("line 15") && e.contains("'Time, Fz'"), "{e}");
        // the same header with other units
        let text = blocks_text(2, "Time,Fz,Fx")
            .replacen("s,N,N", "s,kN,N", 2)
            .replacen("s,kN,N", "s,N,N", 1);
        let e = parse(&text).unwrap_err().to_string();
        assert!(
            e.contains("line 15") && e.contains("units row differs"),
            "{e}"
        );
    }

    #[test]
    fn bare_cr_and_semicolon_fixed_width_with_extra_delimiter() {
        let text = "          TIME;          FF;\r        0,9800;      2,41;;\r        1,9610;      7,99;;\r        2,9390;     14,03;;\r";
        let t = parse(text).unwrap();
        assert_eq!(t.rows, 3);
        assert_eq!(t.columns.len(), 2);
        assert_eq!(t.columns[0].name, "TIME");
        assert_eq!(col(&t, 0), &[0.98, 1.961, 2.939]);
        assert_eq!(col(&t, 1), &[2.41, 7.99, 14.03]);
        assert!(
            t.layout.contains("CR line ends") && t.layout.contains("decimal comma"),
            "{}",
            t.layout
        );
        // the same with LF and CRLF line ends reads the same
        for end in ["\n", "\r\n"] {
            let u = parse(&text.replace('\r', end)).unwrap();
            assert_eq!(u.columns, t.columns);
        }
        // line numbers in errors count CR line ends
        let e = parse("t;F\r0;1\r1;2\r2\r3;4\r").unwrap_err().to_string();
        assert!(e.contains("line 4"), "{e}");
    }
}
