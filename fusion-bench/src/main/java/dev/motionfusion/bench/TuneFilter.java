package dev.motionfusion.bench;

import dev.motionfusion.core.eval.BroadMetric;
import dev.motionfusion.core.eval.ErrorRmse;
import dev.motionfusion.core.eval.Evaluation;
import dev.motionfusion.core.settings.FilterSettingDescriptors;
import dev.motionfusion.core.eval.Trial;
import dev.motionfusion.core.filter.FilterMode;
import dev.motionfusion.core.filter.FilterSettings;
import dev.motionfusion.core.filter.MadgwickFilter;
import dev.motionfusion.core.eval.PhoneComparison;
import dev.motionfusion.core.eval.TrialReader;
import dev.motionfusion.core.input.QuaternionTableReader;
import dev.motionfusion.core.filter.offline.OfflineSettings;

import java.io.File;
import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.HashMap;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Locale;
import java.util.Map;
import java.util.Random;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;

/**
 * Tuning and cross-validation harness for the filter settings (a development tool, not part of
 * the library): loads every trial once into primitive arrays (through the library's trial reader),
 * runs many setting sets over them in memory and scores each with BROAD's metric.
 *
 * <pre>
 * java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.TuneFilter [options] DIR... SET...
 *   DIR          a trial folder or a folder of trial folders; the folder of trial folders names the group
 *   SET          "defaults", "report", or comma-separated name=value overrides of the defaults
 *                ("report:" prefix: overrides of FilterSettings.report()); a label may precede as LABEL@SET
 *   --sets FILE  more sets, one per line (# comments)
 *   --threads N  worker threads (default: available processors)
 *   --trials     print per-trial total/heading/inclination for every set (default: group means only)
 *   --rv         also score each trial's rotation_vector.csv[.gz] (the phone's own orientation)
 *   --cv         cross-validation over the sets: leave one trial out, and tune on one group, test on the other
 *   --lodo       leave one data set out: choose the set best on the other data sets, score it on the one left out
 *                (objective: the worst group's mean over the peer's mean on the same trials with --peers, groups of
 *                one trial left out, else the mean over groups); with --peers, also the first set listed whose
 *                objective is within one standard error of the best (the one-standard-error rule; the error of the
 *                difference, from 400 draws of each group's trials with replacement): list today's settings first
 *   --peers CSV  the peer's figures (input,metric,value[,samples]: fusion-core's test resource peers/vqf.csv);
 *                the metric total_rmse_deg for causal sets, offline_total_rmse_deg for offline ones
 *   --offset SET score the data set SET (a folder of trial folders) with one heading offset per trial removed
 * </pre>
 */
public final class TuneFilter {
    private TuneFilter() {
    }

    /** One trial in primitive arrays. */
    static final class Loaded {
        final String name;
        final String group;
        final String sub; // the group inside the data set: meta.json's venue or motion, else disturbed/undisturbed from the name
        final boolean offsetRemoved;
        final long[] tNs;
        final double[] rows; // 9 per row
        final boolean hasMag;
        final double[][] truth;
        final boolean[] movement;
        final double[][] rotationVector; // null without one
        final File dir;

        Loaded(File dir, boolean withRv, List<String> offsetSets) throws IOException {
            this.dir = dir;
            Trial t = Trial.Companion.load(dir);
            name = t.getName();
            group = dir.getParentFile().getName();
            sub = subGroup(dir, name);
            offsetRemoved = offsetSets.contains(group);
            long[] times = new long[1 << 16];
            double[] imu = new double[9 << 16];
            List<double[]> truthRows = new ArrayList<>();
            List<Boolean> scored = new ArrayList<>();
            int n = 0;
            boolean mag;
            try (TrialReader r = t.open()) {
                mag = r.getHasMag();
                while (r.next()) {
                    if (n == times.length) {
                        times = Arrays.copyOf(times, 2 * n);
                        imu = Arrays.copyOf(imu, 18 * n);
                    }
                    times[n] = Math.round(r.getTimeS() * 1e9);
                    System.arraycopy(r.getImu(), 0, imu, 9 * n, 9);
                    truthRows.add(r.getTruth().clone());
                    scored.add(r.getScored());
                    n++;
                }
            }
            tNs = Arrays.copyOf(times, n);
            rows = Arrays.copyOf(imu, 9 * n);
            hasMag = mag;
            truth = truthRows.toArray(new double[0][]);
            movement = new boolean[n];
            for (int i = 0; i < n; i++) movement[i] = scored.get(i);
            File rv = PhoneComparison.rotationVectorFile(dir);
            if (withRv && rv != null) {
                List<double[]> q = new ArrayList<>();
                try (QuaternionTableReader r = QuaternionTableReader.open(rv.toPath())) {
                    while (r.next()) q.add(r.getQ().clone());
                }
                if (q.size() != n) throw new IllegalArgumentException(rv + ": " + q.size() + " rows, input has " + n);
                rotationVector = q.toArray(new double[0][]);
            } else {
                rotationVector = null;
            }
        }

        /** The offline estimate (Replayer.runOffline through the library's trial evaluation; reads the trial's files). */
        ErrorRmse run(FilterSettings s, OfflineSettings offline) {
            if (offline == null) return run(s);
            if (!offsetRemoved) return Evaluation.INSTANCE.evaluate(Trial.Companion.load(dir), s, offline).getError();
            // Heading offset removed: the offline estimate collected, then scored as the causal one is.
            double[][] est = new double[tNs.length][];
            int[] i = {0};
            Evaluation.INSTANCE.runOffline(Trial.Companion.load(dir), s, offline, (q, truthRow, scored) -> {
                est[i[0]++] = q.clone();
                return kotlin.Unit.INSTANCE;
            });
            if (i[0] != tNs.length) throw new IllegalStateException(name + ": " + i[0] + " offline rows, " + tNs.length + " loaded");
            return BroadMetric.INSTANCE.rmse(est, truth, movement, true);
        }

        ErrorRmse run(FilterSettings s) {
            MadgwickFilter f = new MadgwickFilter(s);
            int n = tNs.length;
            double[][] est = new double[n][4];
            double[] r = rows;
            for (int i = 0; i < n; i++) {
                int k = 9 * i;
                if (hasMag) {
                    f.update(tNs[i], r[k], r[k + 1], r[k + 2], r[k + 3], r[k + 4], r[k + 5], r[k + 6], r[k + 7], r[k + 8]);
                } else {
                    f.update(tNs[i], r[k], r[k + 1], r[k + 2], r[k + 3], r[k + 4], r[k + 5]);
                }
                f.orientationInto(est[i], 0);
            }
            boolean sixD = s.getMode() == FilterMode.IMU || !hasMag || offsetRemoved;
            return BroadMetric.INSTANCE.rmse(est, truth, movement, sixD);
        }
    }

    /** The group of a trial inside its data set: disturbed/undisturbed from the name, else meta.json's "venue" or "motion" string. */
    static String subGroup(File dir, String name) throws IOException {
        if (name.contains("undisturbed") || name.contains("NoDist")) return "undisturbed";
        if (name.contains("disturbed") || name.contains("Dist")) return "disturbed";
        File meta = new File(dir, "meta.json");
        if (meta.isFile()) {
            String text = Files.readString(meta.toPath(), StandardCharsets.UTF_8);
            for (String key : new String[] {"venue", "motion"}) {
                java.util.regex.Matcher m = java.util.regex.Pattern.compile("\"" + key + "\"\\s*:\\s*\"([^\"]*)\"").matcher(text);
                if (m.find()) return m.group(1);
            }
        }
        return "all";
    }

    /** The properties of OfflineSettings in its constructor's order. */
    static final String[] OFFLINE_NAMES = {"backwardWeight", "inclinationBackwardWeight", "headingSmoothing", "smootherRestNoise", "smootherMotionNoise",
        "smootherHeadingNoise", "smootherBiasNoise", "smootherRestSpread", "buildingPersistence"};

    /**
     * The offline settings of [spec] ("offline:" before the overrides, OfflineSettings' properties among
     * them by name, the smoother's noises in degrees), or null for the causal filter.
     */

    static OfflineSettings parseOffline(String spec) {
        String body = spec.contains("@") ? spec.substring(spec.indexOf('@') + 1) : spec;
        if (!body.startsWith("offline")) return null;
        OfflineSettings d = new OfflineSettings();
        double[] v = {d.getBackwardWeight(), d.getInclinationBackwardWeight(), d.getHeadingSmoothing(), d.getSmootherRestNoise(), d.getSmootherMotionNoise(),
            d.getSmootherHeadingNoise(), d.getSmootherBiasNoise(), d.getSmootherRestSpread(), d.getBuildingPersistence()};
        for (String a : body.substring("offline".length()).replaceFirst("^:", "").split(",")) {
            String t = a.trim();
            for (int k = 0; k < OFFLINE_NAMES.length; k++) {
                if (t.startsWith(OFFLINE_NAMES[k] + "=")) {
                    double x = Double.parseDouble(t.substring(OFFLINE_NAMES[k].length() + 1));
                    v[k] = k >= 3 && k <= 6 ? Math.toRadians(x) : x; // the smoother's noises in degrees here
                }
            }
        }
        return new OfflineSettings(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8]);
    }

    static boolean offlineName(String a) {
        for (String n : OFFLINE_NAMES) if (a.trim().startsWith(n + "=")) return true;
        return false;
    }

    static FilterSettings parse(String spec) {
        String body = spec.contains("@") ? spec.substring(spec.indexOf('@') + 1) : spec;
        if (body.startsWith("offline")) {
            StringBuilder kept = new StringBuilder();
            for (String a : body.substring("offline".length()).replaceFirst("^:", "").split(",")) {
                if (a.isBlank() || offlineName(a)) continue;
                if (kept.length() > 0) kept.append(',');
                kept.append(a.trim());
            }
            body = kept.length() == 0 ? "defaults" : kept.toString();
        }
        FilterSettings s = new FilterSettings();
        if (body.equals("defaults")) return s;
        if (body.startsWith("report")) {
            s = FilterSettings.report();
            body = body.substring("report".length());
            if (body.startsWith(":")) body = body.substring(1);
        }
        for (String a : body.split(",")) {
            if (!a.isBlank()) s = FilterSettingDescriptors.apply(s, a.trim());
        }
        return s;
    }

    static String label(String spec) {
        return spec.contains("@") ? spec.substring(0, spec.indexOf('@')) : spec;
    }

    public static void main(String[] args) throws Exception {
        List<File> dirs = new ArrayList<>();
        List<String> specs = new ArrayList<>();
        int threads = Runtime.getRuntime().availableProcessors();
        boolean perTrial = false;
        boolean rv = false;
        boolean cv = false;
        List<String> offsetSets = new ArrayList<>();
        boolean lodo = false;
        Map<String, Double> peers = new LinkedHashMap<>();
        for (int i = 0; i < args.length; i++) {
            String a = args[i];
            switch (a) {
                case "--threads" -> threads = Integer.parseInt(args[++i]);
                case "--trials" -> perTrial = true;
                case "--rv" -> rv = true;
                case "--cv" -> cv = true;
                case "--offset" -> offsetSets.add(args[++i]);
                case "--lodo" -> lodo = true;
                case "--peers" -> {
                    for (String line : Files.readAllLines(new File(args[++i]).toPath(), StandardCharsets.UTF_8)) {
                        String[] c = line.split(",");
                        if (c.length < 3 || line.startsWith("#")) continue;
                        try {
                            peers.put(c[0] + "," + c[1], Double.parseDouble(c[2]));
                        } catch (NumberFormatException e) {
                            // a header or a "—" (no figure)
                        }
                    }
                }
                case "--sets" -> {
                    for (String line : Files.readAllLines(new File(args[++i]).toPath(), StandardCharsets.UTF_8)) {
                        String l = line.strip();
                        if (!l.isEmpty() && !l.startsWith("#")) specs.add(l);
                    }
                }
                default -> {
                    if (new File(a).isDirectory()) dirs.add(new File(a));
                    else specs.add(a);
                }
            }
        }
        if (dirs.isEmpty()) throw new IllegalArgumentException("no trial folder given");
        if (specs.isEmpty()) specs.add("defaults");
        List<FilterSettings> settings = new ArrayList<>();
        for (String s : specs) settings.add(parse(s));
        List<OfflineSettings> offline = new ArrayList<>();
        for (String s : specs) offline.add(parseOffline(s));

        long t0 = System.nanoTime();
        ExecutorService pool = Executors.newFixedThreadPool(threads);
        try {
            run(pool, dirs, specs, settings, offline, perTrial, rv, cv, offsetSets, t0, lodo, peers);
        } finally {
            // A trial that fails to load must end the run, not leave the workers waiting for more work.
            pool.shutdownNow();
        }
    }

    static void run(ExecutorService pool, List<File> dirs, List<String> specs, List<FilterSettings> settings, List<OfflineSettings> offline,
                    boolean perTrial, boolean rv, boolean cv, List<String> offsetSets, long t0, boolean lodo, Map<String, Double> peers) throws Exception {
        List<File> trialDirs = Evaluation.INSTANCE.findTrials(dirs);
        final boolean withRv = rv;
        List<Future<Loaded>> lf = new ArrayList<>();
        for (File d : trialDirs) lf.add(pool.submit(() -> new Loaded(d, withRv, offsetSets)));
        List<Loaded> trials = new ArrayList<>();
        for (Future<Loaded> f : lf) trials.add(f.get());
        System.err.printf(Locale.ROOT, "loaded %d trials in %.1f s%n", trials.size(), (System.nanoTime() - t0) * 1e-9);

        t0 = System.nanoTime();
        ErrorRmse[][] res = new ErrorRmse[settings.size()][trials.size()];
        List<Future<?>> jobs = new ArrayList<>();
        for (int si = 0; si < settings.size(); si++) {
            for (int ti = 0; ti < trials.size(); ti++) {
                final int a = si;
                final int b = ti;
                jobs.add(pool.submit(() -> {
                    res[a][b] = trials.get(b).run(settings.get(a), offline.get(a));
                }));
            }
        }
        for (Future<?> j : jobs) j.get();
        System.err.printf(Locale.ROOT, "ran %d sets in %.1f s%n", settings.size(), (System.nanoTime() - t0) * 1e-9);

        Map<String, List<Integer>> groups = new LinkedHashMap<>();
        for (int ti = 0; ti < trials.size(); ti++) groups.computeIfAbsent(trials.get(ti).group, k -> new ArrayList<>()).add(ti);

        if (rv) {
            System.out.println("## rotation vector (the phone's own orientation)");
            System.out.println("| trial | total | heading | inclination |");
            for (Map.Entry<String, List<Integer>> g : groups.entrySet()) {
                double[] sum = new double[3];
                int count = 0;
                for (int ti : g.getValue()) {
                    Loaded t = trials.get(ti);
                    if (t.rotationVector == null) continue;
                    ErrorRmse e = BroadMetric.INSTANCE.rmse(t.rotationVector, t.truth, t.movement, false);
                    System.out.printf(Locale.ROOT, "| %s | %.2f | %.2f | %.2f |%n", t.name, e.getTotalDeg(), e.getHeadingDeg(), e.getInclinationDeg());
                    sum[0] += e.getTotalDeg();
                    sum[1] += e.getHeadingDeg();
                    sum[2] += e.getInclinationDeg();
                    count++;
                }
                if (count > 0) System.out.printf(Locale.ROOT, "| **%s mean** | %.2f | %.2f | %.2f |%n", g.getKey(), sum[0] / count, sum[1] / count, sum[2] / count);
            }
        }

        for (int si = 0; si < settings.size(); si++) {
            StringBuilder line = new StringBuilder(label(specs.get(si)));
            for (Map.Entry<String, List<Integer>> g : groups.entrySet()) {
                double[] m = mean(res[si], g.getValue());
                line.append(String.format(Locale.ROOT, " | %s %.2f (h %.2f, i %.2f)", g.getKey(), m[0], m[1], m[2]));
            }
            System.out.println(line);
            StringBuilder subs = new StringBuilder("    groups:");
            for (Map.Entry<String, List<Integer>> g : subGroups(trials).entrySet()) {
                subs.append(String.format(Locale.ROOT, " %s %.2f", g.getKey(), mean(res[si], g.getValue())[0]));
            }
            System.out.println(subs);
            if (perTrial) {
                for (int ti = 0; ti < trials.size(); ti++) {
                    ErrorRmse e = res[si][ti];
                    System.out.printf(Locale.ROOT, "    %-40s %6.2f %6.2f %6.2f%n", trials.get(ti).name, e.getTotalDeg(), e.getHeadingDeg(), e.getInclinationDeg());
                }
            }
        }
        if (cv) crossValidate(specs, trials, groups, res);
        if (lodo) leaveOneDataSetOut(specs, offline, trials, res, peers);
    }

    /** The peer's figure for trial [t] (NaN without one). */
    static double peer(Map<String, Double> peers, Loaded t, boolean offline) {
        Double v = peers.get(t.group + "/" + t.name + "," + (offline ? "offline_total_rmse_deg" : "total_rmse_deg"));
        return v == null ? Double.NaN : v;
    }

    /**
     * The objective of set [si] on the data sets other than [heldOut]: the largest ratio of a group's mean to the peer's
     * mean on the same trials (with peer figures), else the mean over the groups of their means.
     */
    static double lodoObjective(int si, String heldOut, List<Loaded> trials, ErrorRmse[][] res, Map<String, Double> peers, boolean offline) {
        return lodoObjective(si, heldOut, trials, res, peers, offline, false);
    }

    /**
     * [lodoObjective], or with [meanRatio] the mean over the groups of the ratio to the peer (the tie-break between
     * sets whose worst group is the same, as when that group does not move with the setting).
     */
    static double lodoObjective(int si, String heldOut, List<Loaded> trials, ErrorRmse[][] res, Map<String, Double> peers, boolean offline, boolean meanRatio) {
        return lodoObjective(si, heldOut, trials, res, peers, offline, meanRatio, null);
    }

    /**
     * The same over the trials of [draw] (per group, positions in that group's list of trials, drawn with replacement),
     * or over every trial once when null. With peer figures, groups of a single trial are left out.
     */
    static double lodoObjective(int si, String heldOut, List<Loaded> trials, ErrorRmse[][] res, Map<String, Double> peers, boolean offline, boolean meanRatio,
                                Map<String, int[]> draw) {
        double worst = 0;
        double ratioSum = 0;
        double sum = 0;
        int n = 0;
        boolean ratio = !peers.isEmpty();
        for (Map.Entry<String, List<Integer>> g : subGroups(trials).entrySet()) {
            List<Integer> members = g.getValue();
            if (trials.get(members.get(0)).group.equals(heldOut)) continue;
            if (ratio && members.size() < 2) continue;
            int[] at = draw == null ? null : draw.get(g.getKey());
            double ours = 0;
            double p = 0;
            for (int k = 0; k < members.size(); k++) {
                int ti = members.get(at == null ? k : at[k]);
                ours += res[si][ti].getTotalDeg();
                if (ratio) p += peer(peers, trials.get(ti), offline);
            }
            ours /= members.size();
            if (ratio) {
                p /= members.size();
                if (Double.isNaN(p)) throw new IllegalArgumentException("no peer figure for a trial of " + g.getKey());
                worst = Math.max(worst, ours / p);
                ratioSum += ours / p;
            }
            sum += ours;
            n++;
        }
        if (meanRatio) return ratio ? ratioSum / n : sum / n;
        return ratio ? worst : sum / n;
    }

    static void leaveOneDataSetOut(List<String> specs, List<OfflineSettings> offline, List<Loaded> trials, ErrorRmse[][] res, Map<String, Double> peers) {
        System.out.println("## leave one data set out (choose the set best on the other data sets, score it on the one left out)");
        List<String> sets = new ArrayList<>();
        for (Loaded t : trials) if (!sets.contains(t.group)) sets.add(t.group);
        for (String held : sets) {
            int b = -1;
            double bo = Double.POSITIVE_INFINITY;
            for (int si = 0; si < specs.size(); si++) {
                double o = lodoObjective(si, held, trials, res, peers, offline.get(si) != null);
                // A tie on the worst group (within 0.1 %) goes to the better mean ratio.
                boolean tie = b >= 0 && Math.abs(o - bo) <= 1e-3 * bo;
                if (tie ? lodoObjective(si, held, trials, res, peers, offline.get(si) != null, true)
                        < lodoObjective(b, held, trials, res, peers, offline.get(b) != null, true) : o < bo) {
                    bo = Math.min(o, bo);
                    b = si;
                }
            }
            StringBuilder line = new StringBuilder(String.format(Locale.ROOT, "held out %s: chosen %s (objective on the others %.3f):", held, label(specs.get(b)), bo));
            System.out.println(line.append(heldOutScore(b, held, trials, res, peers, offline.get(b) != null)));
            if (peers.isEmpty()) continue;
            // The one-standard-error rule: the first set listed within one standard error of the best.
            Random random = new Random(1);
            List<Map<String, int[]>> draws = new ArrayList<>();
            for (int d = 0; d < DRAWS; d++) {
                Map<String, int[]> draw = new HashMap<>();
                for (Map.Entry<String, List<Integer>> g : subGroups(trials).entrySet()) {
                    int[] at = new int[g.getValue().size()];
                    for (int k = 0; k < at.length; k++) at[k] = random.nextInt(at.length);
                    draw.put(g.getKey(), at);
                }
                draws.add(draw);
            }
            double[] best = new double[DRAWS];
            for (int d = 0; d < DRAWS; d++) best[d] = lodoObjective(b, held, trials, res, peers, offline.get(b) != null, false, draws.get(d));
            int within = 0;
            int first = -1;
            for (int si = 0; si < specs.size(); si++) {
                double[] diff = new double[DRAWS];
                double m = 0;
                for (int d = 0; d < DRAWS; d++) {
                    diff[d] = lodoObjective(si, held, trials, res, peers, offline.get(si) != null, false, draws.get(d)) - best[d];
                    m += diff[d] / DRAWS;
                }
                double v = 0;
                for (double x : diff) v += (x - m) * (x - m) / (DRAWS - 1);
                if (lodoObjective(si, held, trials, res, peers, offline.get(si) != null) - bo <= Math.sqrt(v)) {
                    within++;
                    if (first < 0) first = si;
                }
            }
            System.out.println(String.format(Locale.ROOT, "  within one standard error of it: %d set(s); the first listed %s (objective %.3f):", within, label(specs.get(first)),
                lodoObjective(first, held, trials, res, peers, offline.get(first) != null)) + heldOutScore(first, held, trials, res, peers, offline.get(first) != null));
        }
    }

    /** Draws of the trials for the one-standard-error rule. */
    static final int DRAWS = 400;

    /** Set [si]'s mean per group of the data set [held], beside the peer's, and over the data set. */
    static String heldOutScore(int si, String held, List<Loaded> trials, ErrorRmse[][] res, Map<String, Double> peers, boolean offline) {
        StringBuilder line = new StringBuilder();
        for (Map.Entry<String, List<Integer>> g : subGroups(trials).entrySet()) {
            if (!trials.get(g.getValue().get(0)).group.equals(held)) continue;
            double p = 0;
            for (int ti : g.getValue()) p += peer(peers, trials.get(ti), offline);
            p /= g.getValue().size();
            line.append(String.format(Locale.ROOT, " %s %.2f (peer %.2f)", g.getKey(), mean(res[si], g.getValue())[0], p));
        }
        List<Integer> all = new ArrayList<>();
        for (int ti = 0; ti < trials.size(); ti++) if (trials.get(ti).group.equals(held)) all.add(ti);
        return line.append(String.format(Locale.ROOT, "; all %.2f", mean(res[si], all)[0])).toString();
    }

    /** The trials by data set and group inside it ("tyrex-subset/disturbed"). */
    static Map<String, List<Integer>> subGroups(List<Loaded> trials) {
        Map<String, List<Integer>> m = new LinkedHashMap<>();
        for (int ti = 0; ti < trials.size(); ti++) m.computeIfAbsent(trials.get(ti).group + "/" + trials.get(ti).sub, k -> new ArrayList<>()).add(ti);
        return m;
    }

    /** Mean total, heading, inclination over the trials [idx]. */
    static double[] mean(ErrorRmse[] row, List<Integer> idx) {
        double[] m = new double[3];
        for (int ti : idx) {
            m[0] += row[ti].getTotalDeg();
            m[1] += row[ti].getHeadingDeg();
            m[2] += row[ti].getInclinationDeg();
        }
        for (int k = 0; k < 3; k++) m[k] /= idx.size();
        return m;
    }

    /**
     * Objective of a set on the trials not excluded: the mean over groups of each group's mean
     * total RMSE (so a group with more trials does not dominate).
     */
    static double objective(ErrorRmse[] row, Map<String, List<Integer>> groups, int excluded) {
        double sum = 0;
        int ng = 0;
        for (List<Integer> g : groups.values()) {
            double s = 0;
            int c = 0;
            for (int ti : g) {
                if (ti == excluded) continue;
                s += row[ti].getTotalDeg();
                c++;
            }
            if (c > 0) {
                sum += s / c;
                ng++;
            }
        }
        return sum / ng;
    }

    static int best(ErrorRmse[][] res, Map<String, List<Integer>> groups, int excluded) {
        int b = 0;
        for (int si = 1; si < res.length; si++) {
            if (objective(res[si], groups, excluded) < objective(res[b], groups, excluded)) b = si;
        }
        return b;
    }

    static void crossValidate(List<String> specs, List<Loaded> trials, Map<String, List<Integer>> groups, ErrorRmse[][] res) {
        System.out.println("## leave one trial out (choose the set best on the other trials, score it on the one left out)");
        int all = best(res, groups, -1);
        System.out.println("set chosen on all trials: " + label(specs.get(all)));
        int[] chosenCount = new int[specs.size()];
        for (Map.Entry<String, List<Integer>> g : groups.entrySet()) {
            double held = 0;
            double inSample = 0;
            for (int ti : g.getValue()) {
                int b = best(res, groups, ti);
                chosenCount[b]++;
                held += res[b][ti].getTotalDeg();
                inSample += res[all][ti].getTotalDeg();
                System.out.printf(Locale.ROOT, "    %-40s chosen %-30s held-out %6.2f (set chosen on all: %6.2f)%n",
                    trials.get(ti).name, label(specs.get(b)), res[b][ti].getTotalDeg(), res[all][ti].getTotalDeg());
            }
            System.out.printf(Locale.ROOT, "%s: leave-one-out mean %.2f, chosen-on-all mean %.2f%n", g.getKey(), held / g.getValue().size(), inSample / g.getValue().size());
        }
        for (int si = 0; si < specs.size(); si++) {
            if (chosenCount[si] > 0) System.out.println("    chosen " + chosenCount[si] + "×: " + label(specs.get(si)));
        }
        if (groups.size() == 2) {
            System.out.println("## tune on one group, test on the other");
            List<String> names = new ArrayList<>(groups.keySet());
            for (int k = 0; k < 2; k++) {
                String train = names.get(k);
                String test = names.get(1 - k);
                int b = 0;
                for (int si = 1; si < res.length; si++) {
                    if (mean(res[si], groups.get(train))[0] < mean(res[b], groups.get(train))[0]) b = si;
                }
                System.out.printf(Locale.ROOT, "tuned on %s: %s → %s %.2f, %s %.2f%n", train, label(specs.get(b)),
                    train, mean(res[b], groups.get(train))[0], test, mean(res[b], groups.get(test))[0]);
            }
        }
    }
}
