/*
 * CPU time per MadgwickFilter update, measured with the thread's CPU clock: a check of the JMH
 * figures that does not count time the thread spends descheduled on a shared machine.
 * Run: java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.CpuTimePerUpdate
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.filter.FilterMode;
import dev.motionfusion.core.filter.FilterSettings;
import dev.motionfusion.core.filter.MadgwickFilter;
import dev.motionfusion.core.settings.FilterSettingDescriptors;
import dev.motionfusion.core.sim.MotionSimulator;
import dev.motionfusion.core.sim.SimulatedSample;
import dev.motionfusion.core.sim.SimulationSettings;
import java.lang.management.ManagementFactory;
import java.lang.management.ThreadMXBean;
import java.util.List;

public final class CpuTimePerUpdate {
    private static final int N = 4096;
    private static final long UPDATES = 50_000_000L;

    public static void main(String[] args) {
        List<SimulatedSample> samples = new MotionSimulator(new SimulationSettings()).run();
        double[] data = new double[9 * N];
        for (int k = 0; k < N; k++) {
            SimulatedSample s = samples.get(k);
            double[] row = {s.getGyro().getX(), s.getGyro().getY(), s.getGyro().getZ(), s.getAcc().getX(), s.getAcc().getY(),
                s.getAcc().getZ(), s.getMag().getX(), s.getMag().getY(), s.getMag().getZ()};
            System.arraycopy(row, 0, data, 9 * k, 9);
        }
        ThreadMXBean bean = ManagementFactory.getThreadMXBean();
        // The same variants as FilterBenchmark's.
        String[] names = {"report-marg", "report-imu", "defaults", "trust"};
        FilterSettings[] settings = {FilterSettings.report(), FilterSettings.report(FilterMode.IMU), new FilterSettings(),
            FilterSettingDescriptors.apply(new FilterSettings(), "magTrustSpread=0.005")};
        for (int v = 0; v < names.length; v++) {
            boolean marg = settings[v].getMode() == FilterMode.MARG;
            double best = Double.MAX_VALUE;
            for (int round = 0; round < 5; round++) {
                MadgwickFilter filter = new MadgwickFilter(settings[v]);
                long start = bean.getCurrentThreadCpuTime();
                run(filter, data, marg);
                double ns = (bean.getCurrentThreadCpuTime() - start) / (double) UPDATES;
                if (round > 0) best = Math.min(best, ns); // round 0 warms up
            }
            System.out.printf("%-12s %6.1f ns CPU per update  %5.1f M updates/s%n", names[v], best, 1e3 / best);
        }
    }

    private static void run(MadgwickFilter filter, double[] data, boolean marg) {
        long t = 0;
        for (long u = 0; u < UPDATES; u++) {
            int o = 9 * (int) (u & (N - 1));
            t += 5_000_000L;
            if (marg) {
                filter.update(t, data[o], data[o + 1], data[o + 2], data[o + 3], data[o + 4], data[o + 5], data[o + 6], data[o + 7], data[o + 8]);
            } else {
                filter.update(t, data[o], data[o + 1], data[o + 2], data[o + 3], data[o + 4], data[o + 5]);
            }
        }
    }
}
