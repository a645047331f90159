package dev.motionfusion.bench;

import dev.motionfusion.core.AccelerationKt;
import dev.motionfusion.core.input.Recording;
import dev.motionfusion.core.replay.ReplayListener;
import dev.motionfusion.core.replay.ReplayStep;
import dev.motionfusion.core.replay.Replayer;
import dev.motionfusion.core.event.SensorEvents;
import dev.motionfusion.core.event.SessionStream;

import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;

/**
 * Tilt check for real recordings without ground truth (a development tool, not part of the
 * library): replays a recording as `fusion replay` does and prints, per second from FROM to TO, the
 * RMS angle between the filter's up (in the device frame) and the measured specific force over the
 * samples whose magnitude is within 0.3 m/s² of standard gravity. Where the phone is still this is
 * the tilt error; where it moves it bounds it from above (linear acceleration is in the angle).
 *
 * <pre>
 * java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.TiltAfterMotion RECORDING FROM TO SET...
 *   SET  as for TuneFilter: "defaults", "report", or comma-separated name=value overrides, LABEL@ allowed
 * </pre>
 */
public final class TiltAfterMotion {
    private TiltAfterMotion() {
    }

    public static void main(String[] args) throws Exception {
        String path = args[0];
        int from = Integer.parseInt(args[1]);
        int to = Integer.parseInt(args[2]);
        List<String> specs = new ArrayList<>();
        for (int i = 3; i < args.length; i++) specs.add(args[i]);
        if (specs.isEmpty()) specs.add("defaults");
        StringBuilder head = new StringBuilder("| settings |");
        for (int s = from; s < to; s++) head.append(' ').append(s).append("–").append(s + 1).append(" s |");
        System.out.println(head);
        for (String spec : specs) {
            double[] sum = new double[to - from];
            int[] count = new int[to - from];
            try (Recording rec = Recording.Companion.open(Paths.get(path), new dev.motionfusion.core.input.ImportOptions());
                 SensorEvents events = rec.events(rec.getStreams())) {
                new Replayer(TuneFilter.parse(spec)).run(events, rec.getOriginNs(), new ReplayListener() {
                    @Override
                    public void step(ReplayStep step) {
                        if (!step.getInitialised()) return;
                        int k = (int) Math.floor(step.getTimeS()) - from;
                        if (k < 0 || k >= sum.length) return;
                        double[] a = step.getSpecificForce();
                        double n = Math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
                        if (!(Math.abs(n - AccelerationKt.STANDARD_GRAVITY) < 0.3)) return;
                        double[] q = step.getOrientation();
                        double ux = 2 * (q[1] * q[3] - q[0] * q[2]);
                        double uy = 2 * (q[2] * q[3] + q[0] * q[1]);
                        double uz = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
                        double c = Math.max(-1.0, Math.min(1.0, (ux * a[0] + uy * a[1] + uz * a[2]) / n));
                        double deg = Math.toDegrees(Math.acos(c));
                        sum[k] += deg * deg;
                        count[k]++;
                    }

                    @Override
                    public void reference(SessionStream stream, long timestampNs, double[] values) {
                    }
                }, null);
            }
            StringBuilder line = new StringBuilder("| " + TuneFilter.label(spec) + " |");
            for (int k = 0; k < sum.length; k++) {
                line.append(count[k] == 0 ? " — |" : String.format(Locale.ROOT, " %.1f |", Math.sqrt(sum[k] / count[k])));
            }
            System.out.println(line);
        }
    }
}
