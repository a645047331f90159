package dev.motionfusion.bench;

import dev.motionfusion.core.Orientations;
import dev.motionfusion.core.filter.FilterDiagnostics;
import dev.motionfusion.core.filter.MadgwickFilter;
import dev.motionfusion.core.eval.Evaluation;
import dev.motionfusion.core.input.QuaternionTableReader;

import java.io.File;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Locale;

/**
 * Heading error during and after each magnetic disturbance of trials with ground truth (a development tool,
 * not part of the library; docs/ACCURACY.md, "Magnetic disturbance").
 *
 * <p>The disturbances are found from the truth, not from any filter: each magnetometer reading is turned into
 * the earth frame (ENU, y magnetic north) with the reference orientation; a reading whose horizontal direction
 * departs from the trial's median field direction by more than --heading degrees, or whose magnitude departs from
 * the median magnitude by more than --norm (a fraction), is disturbed. Disturbed readings less than 1 s apart form
 * one interval; intervals shorter than --min seconds are left out. For each interval the report gives the field's
 * largest departure, the share of its steps the filter's detector flagged, and the heading error (signed, °) of
 * the filter: at the start, largest during, at the end, RMS during and RMS over the --after seconds after it (or up
 * to the next interval); then the same for a second estimate read from a file (e.g. VQF's, from
 * fusion-bench/python/vqf_peers.py ROWS OUT), and the heading error that integrating the gyroscope alone, from the
 * true orientation at the start with the filter's bias estimate of that moment, has reached at the end (what
 * "no faster than gyroscope integration" means on that interval). Per trial: the detector's flags on undisturbed
 * and disturbed steps, and the heading RMSE of both estimates on each.
 *
 * <pre>
 * java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.MagDisturbanceReport [options] DIR... [SET]
 *   DIR            a trial folder or a folder of trial folders
 *   SET            as for TuneFilter (default: defaults)
 *   --peer DIR     DIR/TRIAL.csv (t_s,qw,qx,qy,qz, ENU, one row per input row) is scored beside the filter
 *   --heading DEG  field direction threshold (default 10)
 *   --norm FRAC    field magnitude threshold (default 0.1)
 *   --min S        shortest interval reported (default 1)
 *   --after S      the window after an interval (default 10)
 * </pre>
 */
public final class MagDisturbanceReport {
    private MagDisturbanceReport() {
    }

    /** With --series S: one line every S seconds per trial (field departure, heading errors, flag, vertical bias). */
    static double series = 0;

    public static void main(String[] args) throws Exception {
        List<File> dirs = new ArrayList<>();
        String spec = "defaults";
        File peerDir = null;
        double headingThr = 10;
        double normThr = 0.1;
        double minLen = 1;
        double after = 10;
        for (int i = 0; i < args.length; i++) {
            switch (args[i]) {
                case "--peer" -> peerDir = new File(args[++i]);
                case "--heading" -> headingThr = Double.parseDouble(args[++i]);
                case "--norm" -> normThr = Double.parseDouble(args[++i]);
                case "--min" -> minLen = Double.parseDouble(args[++i]);
                case "--after" -> after = Double.parseDouble(args[++i]);
                case "--series" -> series = Double.parseDouble(args[++i]);
                default -> {
                    if (new File(args[i]).isDirectory()) dirs.add(new File(args[i]));
                    else spec = args[i];
                }
            }
        }
        System.out.println("settings: " + TuneFilter.label(spec) + "; disturbed: field direction > " + headingThr
            + "° or magnitude > " + (100 * normThr) + " % from the trial's median");
        System.out.println("| trial | interval (s) | field Δdir max / Δ|m| max | flagged | filter: start / max / end, RMS during, RMS after"
            + (peerDir != null ? " | peer: start / max / end, RMS during, RMS after" : "") + " | gyroscope alone at the end |");
        List<String> summary = new ArrayList<>();
        for (File d : Evaluation.INSTANCE.findTrials(dirs)) {
            TuneFilter.Loaded t = new TuneFilter.Loaded(d, false, List.of());
            summary.add(report(t, TuneFilter.parse(spec), peerDir, headingThr, normThr, minLen, after));
        }
        System.out.println();
        System.out.println("| trial | disturbed steps | flagged when undisturbed | flagged when disturbed | filter heading RMSE undisturbed / disturbed"
            + (peerDir != null ? " | peer heading RMSE undisturbed / disturbed" : "") + " |");
        for (String s : summary) System.out.println(s);
    }

    static String report(TuneFilter.Loaded t, dev.motionfusion.core.filter.FilterSettings s, File peerDir,
                         double headingThr, double normThr, double minLen, double after) throws Exception {
        int n = t.tNs.length;
        double[] time = new double[n];
        for (int i = 0; i < n; i++) time[i] = (t.tNs[i] - t.tNs[0]) * 1e-9;
        boolean[] hasTruth = new boolean[n];
        double[] fieldDir = new double[n];
        double[] fieldNorm = new double[n];
        double[] v = new double[3];
        for (int i = 0; i < n; i++) {
            double[] r = t.truth[i];
            hasTruth[i] = r != null && Double.isFinite(r[0]) && t.hasMag;
            if (!hasTruth[i]) continue;
            rotate(r, t.rows[9 * i + 6], t.rows[9 * i + 7], t.rows[9 * i + 8], v);
            fieldDir[i] = Math.atan2(v[0], v[1]);
            fieldNorm[i] = Math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        }
        double refDir = circularMedian(fieldDir, hasTruth);
        double refNorm = median(fieldNorm, hasTruth);
        boolean[] dist = new boolean[n];
        double[] dDir = new double[n];
        double[] dNorm = new double[n];
        for (int i = 0; i < n; i++) {
            if (!hasTruth[i]) continue;
            dDir[i] = Math.toDegrees(Math.abs(wrap(fieldDir[i] - refDir)));
            dNorm[i] = Math.abs(fieldNorm[i] / refNorm - 1);
            dist[i] = dDir[i] > headingThr || dNorm[i] > normThr;
        }

        // The filter, step by step, with its flag and bias.
        MadgwickFilter f = new MadgwickFilter(s);
        double[] own = new double[n];
        boolean[] flagged = new boolean[n];
        double[][] bias = new double[n][];
        double[] q = new double[4];
        double[] e = new double[4];
        for (int i = 0; i < n; i++) {
            int k = 9 * i;
            double[] r = t.rows;
            f.update(t.tNs[i], r[k], r[k + 1], r[k + 2], r[k + 3], r[k + 4], r[k + 5], r[k + 6], r[k + 7], r[k + 8]);
            f.orientationInto(q, 0);
            FilterDiagnostics dg = f.diagnostics();
            flagged[i] = dg.getMagneticDisturbance();
            bias[i] = new double[] {dg.getGyroBias().getX(), dg.getGyroBias().getY(), dg.getGyroBias().getZ()};
            own[i] = hasTruth[i] ? heading(q, t.truth[i], e) : Double.NaN;
        }
        double[] peer = null;
        if (peerDir != null) {
            peer = new double[n];
            Arrays.fill(peer, Double.NaN);
            File pf = new File(peerDir, t.name + ".csv");
            try (QuaternionTableReader r = QuaternionTableReader.open(pf.toPath())) {
                int i = 0;
                while (r.next() && i < n) {
                    if (hasTruth[i]) peer[i] = heading(r.getQ(), t.truth[i], e);
                    i++;
                }
            }
        }

        if (series > 0) {
            double next = 0;
            for (int i = 0; i < n; i++) {
                if (time[i] < next || !hasTruth[i]) continue;
                next = time[i] + series;
                double[] r = t.truth[i];
                // The bias about the true vertical: the sensor-frame bias turned into the earth frame, its z.
                double[] bw = new double[3];
                rotate(r, bias[i][0], bias[i][1], bias[i][2], bw);
                System.out.printf(Locale.ROOT, "  %6.1f s  field %6.1f° %5.1f %%  filter %6.1f  peer %6.1f  %s  bias_up %6.3f °/s  gyro %.2f%n",
                    time[i], Math.toDegrees(wrap(fieldDir[i] - refDir)), 100 * (fieldNorm[i] / refNorm - 1), own[i], peer != null ? peer[i] : Double.NaN,
                    flagged[i] ? "D" : ".", Math.toDegrees(bw[2]), Math.sqrt(t.rows[9 * i] * t.rows[9 * i] + t.rows[9 * i + 1] * t.rows[9 * i + 1] + t.rows[9 * i + 2] * t.rows[9 * i + 2]));
            }
        }
        // Intervals: disturbed steps less than 1 s apart, at least minLen long.
        List<int[]> intervals = new ArrayList<>();
        int start = -1;
        int last = -1;
        for (int i = 0; i < n; i++) {
            if (!dist[i]) continue;
            if (start >= 0 && time[i] - time[last] > 1.0) {
                if (time[last] - time[start] >= minLen) intervals.add(new int[] {start, last});
                start = -1;
            }
            if (start < 0) start = i;
            last = i;
        }
        if (start >= 0 && time[last] - time[start] >= minLen) intervals.add(new int[] {start, last});

        for (int j = 0; j < intervals.size(); j++) {
            int a = intervals.get(j)[0];
            int b = intervals.get(j)[1];
            int endAfter = b + 1;
            int limit = j + 1 < intervals.size() ? intervals.get(j + 1)[0] : n;
            while (endAfter < limit && time[endAfter] - time[b] <= after) endAfter++;
            double maxDir = 0;
            double maxNorm = 0;
            int fl = 0;
            for (int i = a; i <= b; i++) {
                maxDir = Math.max(maxDir, dDir[i]);
                maxNorm = Math.max(maxNorm, dNorm[i]);
                if (flagged[i]) fl++;
            }
            StringBuilder line = new StringBuilder(String.format(Locale.ROOT, "| %s | %.1f–%.1f | %.0f° / %.0f %% | %.0f %% | %s",
                t.name.replace("Guillaume_Nexus5_", ""), time[a], time[b], maxDir, 100 * maxNorm, 100.0 * fl / (b - a + 1),
                describe(own, a, b, endAfter)));
            if (peer != null) line.append(" | ").append(describe(peer, a, b, endAfter));
            line.append(String.format(Locale.ROOT, " | %.1f |", gyroAlone(t, a, b, bias[a])));
            System.out.println(line);
        }

        int undist = 0;
        int dis = 0;
        int flU = 0;
        int flD = 0;
        double[] sq = new double[4];
        for (int i = 0; i < n; i++) {
            if (!hasTruth[i] || !t.movement[i]) continue;
            if (dist[i]) {
                dis++;
                if (flagged[i]) flD++;
                sq[1] += own[i] * own[i];
                if (peer != null) sq[3] += peer[i] * peer[i];
            } else {
                undist++;
                if (flagged[i]) flU++;
                sq[0] += own[i] * own[i];
                if (peer != null) sq[2] += peer[i] * peer[i];
            }
        }
        String sum = String.format(Locale.ROOT, "| %s | %.0f %% | %.0f %% | %.0f %% | %.2f / %.2f",
            t.name.replace("Guillaume_Nexus5_", ""), 100.0 * dis / Math.max(1, dis + undist), 100.0 * flU / Math.max(1, undist),
            100.0 * flD / Math.max(1, dis), Math.sqrt(sq[0] / Math.max(1, undist)), Math.sqrt(sq[1] / Math.max(1, dis)));
        if (peer != null) sum += String.format(Locale.ROOT, " | %.2f / %.2f", Math.sqrt(sq[2] / Math.max(1, undist)), Math.sqrt(sq[3] / Math.max(1, dis)));
        return sum + " |";
    }

    /** start / max / end, RMS during, RMS after, of the signed heading errors h (°). */
    static String describe(double[] h, int a, int b, int endAfter) {
        double max = 0;
        double sq = 0;
        int c = 0;
        for (int i = a; i <= b; i++) {
            if (Double.isNaN(h[i])) continue;
            if (Math.abs(h[i]) > Math.abs(max)) max = h[i];
            sq += h[i] * h[i];
            c++;
        }
        double sqa = 0;
        int ca = 0;
        for (int i = b + 1; i < endAfter; i++) {
            if (Double.isNaN(h[i])) continue;
            sqa += h[i] * h[i];
            ca++;
        }
        return String.format(Locale.ROOT, "%.1f / %.1f / %.1f, %.1f, %s", h[a], max, h[b], Math.sqrt(sq / Math.max(1, c)),
            ca > 0 ? String.format(Locale.ROOT, "%.1f", Math.sqrt(sqa / ca)) : "—");
    }

    /** Heading error (°) at step b of the gyroscope alone, bias [w] removed, started from the truth at step a. */
    static double gyroAlone(TuneFilter.Loaded t, int a, int b, double[] w) {
        double[] q = t.truth[a].clone();
        for (int i = a + 1; i <= b; i++) {
            double dt = (t.tNs[i] - t.tNs[i - 1]) * 1e-9;
            double gx = t.rows[9 * i] - w[0];
            double gy = t.rows[9 * i + 1] - w[1];
            double gz = t.rows[9 * i + 2] - w[2];
            double h = 0.5 * dt;
            double q0 = q[0] + h * (-q[1] * gx - q[2] * gy - q[3] * gz);
            double q1 = q[1] + h * (q[0] * gx + q[2] * gz - q[3] * gy);
            double q2 = q[2] + h * (q[0] * gy - q[1] * gz + q[3] * gx);
            double q3 = q[3] + h * (q[0] * gz + q[1] * gy - q[2] * gx);
            double nn = 1.0 / Math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3);
            q[0] = q0 * nn; q[1] = q1 * nn; q[2] = q2 * nn; q[3] = q3 * nn;
        }
        double[] r = t.truth[b];
        if (r == null || !Double.isFinite(r[0])) return Double.NaN;
        return heading(q, r, new double[4]);
    }

    static double heading(double[] q, double[] r, double[] e) {
        Orientations.errorQuaternion(q, r, e);
        return Math.toDegrees(Orientations.signedHeading(e));
    }

    /** v = q ⊗ [0, x, y, z] ⊗ q*. */
    static void rotate(double[] q, double x, double y, double z, double[] v) {
        double w = q[0], a = q[1], b = q[2], c = q[3];
        v[0] = (1 - 2 * (b * b + c * c)) * x + 2 * (a * b - w * c) * y + 2 * (a * c + w * b) * z;
        v[1] = 2 * (a * b + w * c) * x + (1 - 2 * (a * a + c * c)) * y + 2 * (b * c - w * a) * z;
        v[2] = 2 * (a * c - w * b) * x + 2 * (b * c + w * a) * y + (1 - 2 * (a * a + b * b)) * z;
    }

    static double wrap(double a) {
        return Math.atan2(Math.sin(a), Math.cos(a));
    }

    static double median(double[] x, boolean[] use) {
        double[] v = new double[x.length];
        int c = 0;
        for (int i = 0; i < x.length; i++) if (use[i]) v[c++] = x[i];
        v = Arrays.copyOf(v, c);
        Arrays.sort(v);
        return c == 0 ? Double.NaN : v[c / 2];
    }

    /** The median of the angles' departures from their circular mean, added to that mean. */
    static double circularMedian(double[] x, boolean[] use) {
        double s = 0;
        double c = 0;
        for (int i = 0; i < x.length; i++) {
            if (!use[i]) continue;
            s += Math.sin(x[i]);
            c += Math.cos(x[i]);
        }
        double mean = Math.atan2(s, c);
        double[] d = new double[x.length];
        for (int i = 0; i < x.length; i++) d[i] = use[i] ? wrap(x[i] - mean) : 0;
        return mean + median(d, use);
    }
}
