/*
 * How well two clocks are put on one (docs/SYNC.md): simulated laptop-phone links with known clocks
 * (offsets of seconds, drift from -100 to +100 ppm, each one-way delay 0.3 ms plus a uniform jitter
 * up to 20 ms, pings at 4 Hz), ten minutes each. For a recording mapped afterwards from all its
 * exchanges (ClockTimeline) and for the live estimate (ClockSync, as a link shows it), the error of
 * a phone time put on the laptop's clock, read every 100 ms: median, p99 and maximum, and how often
 * the stated uncertainty held. Also the shortest delays of the two ways made unequal, which no
 * estimate can see: the error then is half the difference, within the stated uncertainty.
 * Run: java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.ClockAlignment [MINUTES]
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.sim.SimulatedClockLink;
import dev.motionfusion.core.sync.ClockExchange;
import dev.motionfusion.core.sync.ClockMapping;
import dev.motionfusion.core.sync.ClockSync;
import dev.motionfusion.core.sync.ClockTimeline;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Locale;

public final class ClockAlignment {
    private static final long SECOND = 1_000_000_000L;

    public static void main(String[] args) {
        int minutes = args.length > 0 ? Integer.parseInt(args[0]) : 10;
        System.out.println("| link | drift (ppm) | recording: median / p99 / max (ms) | within its uncertainty | live: median / p99 / max (ms) |");
        System.out.println("|---|---|---|---|---|");
        double[] drifts = {-100, -50, 0, 50, 100};
        long seed = 1;
        for (boolean asymmetric : new boolean[] {false, true}) {
            for (double drift : drifts) {
                long up = asymmetric ? 3_000_000 : 300_000;
                long down = 300_000;
                SimulatedClockLink link = new SimulatedClockLink((seed * 7919 % 100) * SECOND - 3_210_987_654L, drift, up, down, 20_000_000, 1_000_000, seed);
                SimulatedClockLink same = new SimulatedClockLink(link.getOffsetNs(), drift, up, down, 20_000_000, 1_000_000, seed);
                seed++;
                long start = 5_000 * SECOND;
                int pings = minutes * 60 * 4;
                List<ClockExchange> exchanges = new ArrayList<>(pings);
                for (int k = 0; k < pings; k++) exchanges.add(link.exchange(start + k * SECOND / 4));
                ClockTimeline timeline = new ClockTimeline(exchanges, 150 * SECOND, SECOND);
                int n = minutes * 600;
                double[] recorded = new double[n];
                int held = 0;
                for (int k = 0; k < n; k++) {
                    long t = start + k * SECOND / 10;
                    long phone = link.phoneAt(t);
                    recorded[k] = Math.abs(timeline.toLaptop(phone) - t);
                    if (recorded[k] <= timeline.uncertaintyAt(phone) + 1) held++;
                }
                // Live: the estimate as it stands when each reading is made, after 10 s.
                ClockSync sync = new ClockSync(ClockSync.DEFAULT_WINDOW);
                double[] live = new double[n];
                int m = 0;
                long nextPing = start;
                for (int k = 0; k < n; k++) {
                    long t = start + k * SECOND / 10;
                    while (nextPing <= t) {
                        sync.add(same.exchange(nextPing));
                        nextPing += SECOND / 4;
                    }
                    if (t < start + 10 * SECOND) continue;
                    ClockMapping mapping = sync.mapping();
                    long read = t - 50_000_000;
                    live[m++] = Math.abs(mapping.toLaptop(same.phoneAt(read)) - read);
                }
                live = Arrays.copyOf(live, m);
                System.out.printf(Locale.ROOT, "| %s | %+.0f | %s | %.1f %% | %s |%n",
                    asymmetric ? "3 ms up, 0.3 ms down at the shortest" : "0.3 ms each way at the shortest", drift,
                    stats(recorded), 100.0 * held / n, stats(live));
            }
        }
        System.out.println("(each one-way delay: the shortest plus up to 20 ms of uniform jitter; pings at 4 Hz; " + minutes + " min per row)");
    }

    private static String stats(double[] errorsNs) {
        double[] s = errorsNs.clone();
        Arrays.sort(s);
        return String.format(Locale.ROOT, "%.3f / %.3f / %.3f", s[s.length / 2] / 1e6, s[(int) (s.length * 0.99)] / 1e6, s[s.length - 1] / 1e6);
    }
}
