#!/usr/bin/env python3
"""Writes the fixtures of tests/other_formats.rs from the real record
ground_motions/RSN753_LOMAP_CLS090-hor2.AT2 (Loma Prieta 1989, Corralitos
090, in g, dt = 0.005 s): samples FIRST..FIRST+COUNT-1 (t = 3.5 to 5.095 s,
holding the record's PGA, 0.4828 g at t = 4.055 s) in ESM ASCII, K-NET
ASCII and COSMOS V2, each with a header laid out as those databases write
it. The test reads the same window from the AT2 and checks dt and PGA.

Run from the repository root: python3 crates/motion/tests/data/make_fixtures.py
"""
import os

G = 9.80665
FIRST, COUNT, DT = 700, 320, 0.005
HERE = os.path.dirname(os.path.abspath(__file__))
AT2 = os.path.join(HERE, "../../../../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2")

lines = open(AT2, newline="").read().splitlines()
values_g = [float(x) for line in lines[4:] for x in line.split()]
window = values_g[FIRST:FIRST + COUNT]
gal = [v * G * 100.0 for v in window]
pga = max(abs(v) for v in gal)
t_pga = DT * max(range(COUNT), key=lambda i: abs(gal[i]))


def write(name, text_lines):
    with open(os.path.join(HERE, name), "w", newline="\n") as f:
        f.write("\n".join(text_lines) + "\n")


# ESM ASCII: 64 `KEY: value` header lines, one value per line
esm = [
    "EVENT_NAME: LOMA PRIETA", "EVENT_ID: NC-1989-0001", "EVENT_DATE_YYYYMMDD: 19891018",
    "EVENT_TIME_HHMMSS: 000415", "EVENT_LATITUDE_DEGREE: 37.0400", "EVENT_LONGITUDE_DEGREE: -121.8800",
    "EVENT_DEPTH_KM: 17.5", "HYPOCENTER_REFERENCE: ", "MAGNITUDE_W: 6.9", "MAGNITUDE_W_REFERENCE: ",
    "MAGNITUDE_L: ", "MAGNITUDE_L_REFERENCE: ", "FOCAL_MECHANISM: ", "NETWORK: CE", "STATION_CODE: CLS",
    "STATION_NAME: Corralitos", "STATION_LATITUDE_DEGREE: 37.0460", "STATION_LONGITUDE_DEGREE: -121.8030",
    "STATION_ELEVATION_M: 100", "LOCATION: ", "SENSOR_DEPTH_M: 0", "VS30_M/S: 462",
    "SITE_CLASSIFICATION_EC8: B", "MORPHOLOGIC_CLASSIFICATION: ", "EPICENTRAL_DISTANCE_KM: 7.2",
    "EARTHQUAKE_BACKAZIMUTH_DEGREE: ", "DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS: 19891018_000418.500",
    "DATE_TIME_FIRST_SAMPLE_PRECISION: milliseconds", "SAMPLING_INTERVAL_S: 0.005000",
    "NDATA: %d" % COUNT, "DURATION_S: %.3f" % ((COUNT - 1) * DT), "STREAM: HGE", "UNITS: cm/s^2",
    "INSTRUMENT: ", "INSTRUMENT_ANALOG/DIGITAL: A", "INSTRUMENTAL_FREQUENCY_HZ: ", "INSTRUMENTAL_DAMPING: ",
    "FULL_SCALE_G: ", "N_BIT_DIGITAL_CONVERTER: ", "PGA_CM/S^2: %f" % pga, "TIME_PGA_S: %.3f" % t_pga,
    "BASELINE_CORRECTION: BASELINE REMOVED", "FILTER_TYPE: BUTTERWORTH", "FILTER_ORDER: 2",
    "LOW_CUT_FREQUENCY_HZ: 0.100", "HIGH_CUT_FREQUENCY_HZ: 25.000", "LATE/NORMAL_TRIGGERED: NT",
    "DATABASE_VERSION: ESM 2018", "HEADER_FORMAT: DYNA 1.2", "DATA_TYPE: ACCELERATION", "PROCESSING: manual",
    "DATA_TIMESTAMP_YYYYMMDD_HHMMSS: 20180101_000000.000", "DATA_LICENSE: ", "DATA_CITATION: ",
    "DATA_CREATOR: ", "ORIGINAL_DATA_MEDIATOR_CITATION: ", "ORIGINAL_DATA_MEDIATOR: ",
    "ORIGINAL_DATA_CREATOR_CITATION: ", "ORIGINAL_DATA_CREATOR: ", "USER1: ", "USER2: ", "USER3: ",
    "USER4: ", "USER5: ",
]
assert len(esm) == 64
write("CE.CLS..HGE.D.19891018.000415.C.ACC.ASC", esm + ["%.6E" % v for v in gal])

# K-NET ASCII: counts at 3920 gal / 6182761, 8 per line, with an offset
factor = 3920.0 / 6182761.0
counts = [round(v / factor) + 1234 for v in gal]
mean = sum(counts) / COUNT
max_acc = max(abs(c - mean) for c in counts) * factor
knet = [
    "Origin Time       1989/10/18 17:04:00", "Lat.              37.040", "Long.             -121.880",
    "Depth. (km)       18", "Mag.              6.9", "Station Code      CLS0000", "Station Lat.      37.046",
    "Station Long.     -121.803", "Station Height(m) 100", "Record Time       1989/10/18 17:04:18",
    "Sampling Freq(Hz) 200Hz", "Duration Time(s)  2", "Dir.              E-W",
    "Scale Factor      3920(gal)/6182761", "Max. Acc. (gal)   %.3f" % max_acc,
    "Last Correction   1989/10/18 17:04:00", "Memo.",
]
write("CLS0001910181704.EW", knet + ["".join("%9d" % c for c in counts[i:i + 8]) for i in range(0, COUNT, 8)])

# COSMOS V2: 13 text lines, 100 integer and 100 real header values (-999:
# unknown), data in (8F10.5), whose negative values below -100 touch
ints = [-999] * 100
ints[0], ints[1], ints[2], ints[53] = 2, 1, 4, 90  # V2, acceleration, cm/sec2, azimuth 90
reals = [-999.0] * 100
reals[0], reals[1] = 37.046, -121.803
reals[61], reals[62], reals[63], reals[64] = DT * 1000.0, COUNT * DT, pga, t_pga  # ms, s, peak, time
cosmos = [
    "Corrected acceleration  (Format v01.20 with 13 text lines) Src: quakejoint test",
    "Loma Prieta Earthquake        Oct 18, 1989 00:04:15.0 UTC",
    "Hypocenter: 37.040  -121.880  H= 18km     M=6.9",
    "Origin: 10/18/1989, 00:04:15.0 UTC",
    "Statn No: 57007  Code:CE-CLS  Corralitos",
    "Coords: 37.046  -121.803  Site geology:",
    "Recorder: SMA-1 s/n        (  3 Chns of  3 at Sta)",
    "Rcrd start time:10/18/1989, 00:04:18.5 UTC",
    "Sta Chan   1: 90 deg ( Rcrd Chan  1)",
    "Raw record length = %.3f sec" % (COUNT * DT),
    "Processed: quakejoint test, Max = %.3f cm/sec2 at %.3f sec" % (pga, t_pga),
    "Record filtered below  0.10 Hz",
    "Values used when parameter or data value is unknown/unspecified:   -999, -999.0",
    " 100 Integer-header values follow on 10 lines, Format= (10I8)",
]
cosmos += ["".join("%8d" % v for v in ints[i:i + 10]) for i in range(0, 100, 10)]
cosmos += [" 100 Real-header values follow on 20 lines, Format= (5F15.6)"]
cosmos += ["".join("%15.6f" % v for v in reals[i:i + 5]) for i in range(0, 100, 5)]
cosmos += ['   1 Comment line(s) follow, each starting with a "|":', "| cut from RSN753_LOMAP_CLS090-hor2.AT2"]
cosmos += ["%8d acceleration pts, approx %4d secs, units=cm/sec2 (04), Format=(8F10.5)" % (COUNT, COUNT * DT)]
cosmos += ["".join("%10.5f" % v for v in gal[i:i + 8]) for i in range(0, COUNT, 8)]
cosmos += ["End-of-data for Chan  1 acceleration"]
write("CLS090.V2", cosmos)
