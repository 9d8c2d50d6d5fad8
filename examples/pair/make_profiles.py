#!/usr/bin/env python3
"""Write the pair files and schedules of seed 001's Table 3 (titanium heating profiles).

Each profile starts at 793 K (the seed truncates the curve below it, its sec. 4.2 and fig. 17),
heats at dT/dt_heat to T_max, holds t_Tmax and cools at dT/dt_cool back to 793 K. The pair's
radius is half the tabulated mean diameter. Run from this folder: python3 make_profiles.py
"""

# Exp. ID, mean diameter [um], T_max [K], heating [K/min], cooling [K/min], hold [min]
TABLE3 = """E1B 67.5 1203 20 -20 0
E2B 66.2 1203 20 -20 30
E3B 63.6 1203 20 -20 90
E4B 66.0 1203 20 -20 120
E5B 66.3 1203 20 -20 180
E6B 67.2 1203 50 -50 0
E7B 65.3 1203 50 -50 30
E8B 66.3 1203 50 -50 60
E9B 64.1 1203 50 -50 90
E10B 64.7 1203 50 -50 120
E11B 65.4 1373 20 -20 0
E12B 66.5 1373 20 -20 30
E13B 66.5 1373 20 -20 60
E14B 66.6 1373 20 -20 90
E15B 67.6 1373 20 -20 120
E16B 65.8 1373 50 -50 0
E17B 66.4 1373 50 -50 30
E18B 66.0 1373 50 -50 60
E19B 65.3 1373 50 -50 90
E20B 65.0 1373 50 -50 120
E21B 64.1 1573 20 -20 0
E22B 66.2 1573 20 -20 30
E23B 66.2 1573 20 -20 60
E24B 64.8 1573 20 -20 90
E25B 73.4 1573 20 -20 120
E26B 68.9 1573 50 -50 0
E27B 67.1 1573 50 -50 30
E28B 66.5 1573 50 -50 60"""

T_START = 793.0


def main():
    for line in TABLE3.splitlines():
        name, d, tmax, heat, cool, hold = line.split()
        d, tmax, heat, cool, hold = float(d), float(tmax), float(heat), float(cool), float(hold)
        t1 = (tmax - T_START) / (heat / 60.0)
        t2 = t1 + hold * 60.0
        t3 = t2 + (tmax - T_START) / (-cool / 60.0)
        points = [(0.0, T_START), (t1, tmax)]
        if hold > 0:
            points.append((t2, tmax))
        points.append((t3, T_START))
        with open("%s.csv" % name, "w") as f:
            f.write("time [s],temperature [K]\n")
            for t, temp in points:
                f.write("%.10g,%.10g\n" % (t, temp))
        with open("%s.pair" % name, "w") as f:
            f.write("# Seed 001 table 3, %s: mean diameter %g um, %g K/min to %g K, hold %g min, "
                    "%g K/min back\n# to 793 K (written by make_profiles.py; README.md)\n\n"
                    % (name, d, heat, tmax, hold, cool))
            f.write("[scene]\nname = %s\nunits = SI\n\n" % name)
            f.write("[pair]\nmaterials = titanium.materials\nmaterial = titanium\n")
            f.write("radius = %.6g\nschedule = %s.csv\noutput_interval = 60\n" % (d * 0.5e-6, name))


if __name__ == "__main__":
    main()
