/*
 * JMH benchmarks of one MadgwickFilter update, on simulated samples (200 Hz, noise, bias).
 * Run: java -jar fusion-bench/target/benchmarks.jar -prof gc  (see docs/BENCHMARKS.md).
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.filter.FilterMode;
import dev.motionfusion.core.filter.FilterSettings;
import dev.motionfusion.core.filter.MadgwickFilter;
import dev.motionfusion.core.settings.FilterSettingDescriptors;
import dev.motionfusion.core.sim.MotionSimulator;
import dev.motionfusion.core.sim.SimulatedSample;
import dev.motionfusion.core.sim.SimulationSettings;
import java.util.List;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.Warmup;

@State(Scope.Thread)
@BenchmarkMode(Mode.Throughput)
@OutputTimeUnit(TimeUnit.MICROSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(1)
public class FilterBenchmark {
    /**
     * report-marg: the report's MARG update with ζ; report-imu: its IMU update; defaults: FilterSettings();
     * trust: the defaults with the magnetic trust at its value for walks through buildings (magTrustSpread 0.005).
     */
    @Param({"report-marg", "report-imu", "defaults", "trust"})
    public String variant;

    private static final int N = 4096;
    private static final long PERIOD_NS = 5_000_000L;
    private final double[] data = new double[9 * N];
    private MadgwickFilter filter;
    private boolean marg;
    private long t;
    private int i;

    @Setup(Level.Trial)
    public void setUp() {
        FilterSettings settings;
        switch (variant) {
            case "report-marg": settings = FilterSettings.report(); break;
            case "report-imu": settings = FilterSettings.report(FilterMode.IMU); break;
            case "defaults": settings = new FilterSettings(); break;
            case "trust": settings = FilterSettingDescriptors.apply(new FilterSettings(), "magTrustSpread=0.005"); break;
            default: throw new IllegalArgumentException(variant);
        }
        marg = settings.getMode() == FilterMode.MARG;
        List<SimulatedSample> samples = new MotionSimulator(new SimulationSettings()).run();
        for (int k = 0; k < N; k++) {
            SimulatedSample s = samples.get(k);
            double[] row = {s.getGyro().getX(), s.getGyro().getY(), s.getGyro().getZ(), s.getAcc().getX(), s.getAcc().getY(),
                s.getAcc().getZ(), s.getMag().getX(), s.getMag().getY(), s.getMag().getZ()};
            System.arraycopy(row, 0, data, 9 * k, 9);
        }
        filter = new MadgwickFilter(settings);
    }

    /** One update (gyroscope, accelerometer and, for MARG, magnetometer sampled together). */
    @Benchmark
    public void update() {
        int o = 9 * i;
        t += PERIOD_NS;
        if (marg) {
            filter.update(t, data[o], data[o + 1], data[o + 2], data[o + 3], data[o + 4], data[o + 5], data[o + 6], data[o + 7], data[o + 8]);
        } else {
            filter.update(t, data[o], data[o + 1], data[o + 2], data[o + 3], data[o + 4], data[o + 5]);
        }
        i = (i + 1) & (N - 1);
    }
}
