/*
 * What the live stream's JSON costs against a compact binary form: the messages of seven sensor streams at
 * 200 Hz and the orientation (1,600 a second), with values as a phone gives them (noisy readings whose
 * shortest decimals have 7-9 significant digits, nanosecond timestamps of 14 digits, a unit quaternion
 * in doubles), encoded by StreamCodec.encodeTo into one reused StringBuilder as the server's sender does.
 * Reports the encode time per message (single thread, after warm-up; best of five rounds), the JSON bytes
 * per message and per second, and the bytes the same content takes in a binary form (1 byte type and
 * stream, 8 bytes timestamp, 4 per float value, 1 accuracy; the orientation as 4 doubles, its angles
 * left to the reader), each with the WebSocket frame header (2 bytes below 126 bytes of payload, 4 above).
 * Run: java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.StreamEncodeCost
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.event.SessionStream;
import dev.motionfusion.core.stream.StreamCodec;
import dev.motionfusion.core.stream.StreamMessage;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import java.util.SplittableRandom;

public final class StreamEncodeCost {
    private static final List<SessionStream> STREAMS = List.of(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE,
        SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE_UNCALIBRATED, SessionStream.MAGNETOMETER_UNCALIBRATED,
        SessionStream.ROTATION_VECTOR, SessionStream.GAME_ROTATION_VECTOR);

    public static void main(String[] args) {
        int rounds = 20_000; // of 8 messages: 100 s of the stream
        List<StreamMessage> messages = messages(rounds);
        long jsonBytes = 0;
        long binaryBytes = 0;
        long jsonFramed = 0;
        long binaryFramed = 0;
        StringBuilder sb = new StringBuilder(256);
        for (StreamMessage m : messages) {
            sb.setLength(0);
            StreamCodec.encodeTo(sb, m);
            int json = sb.toString().getBytes(StandardCharsets.UTF_8).length;
            int binary = binarySize(m);
            jsonBytes += json;
            binaryBytes += binary;
            jsonFramed += json + frameHeader(json);
            binaryFramed += binary + frameHeader(binary);
        }
        int n = messages.size();
        long sink = 0;
        for (int w = 0; w < 5; w++) sink += encodeAll(messages, sb); // warm-up
        long best = Long.MAX_VALUE;
        for (int r = 0; r < 5; r++) {
            long t0 = System.nanoTime();
            sink += encodeAll(messages, sb);
            best = Math.min(best, System.nanoTime() - t0);
        }
        double nsPerMessage = (double) best / n;
        double perSecond = 1600;
        System.out.printf(Locale.ROOT, "%d messages (7 streams at 200 Hz and the orientation, %d s)%n", n, rounds / 200);
        System.out.printf(Locale.ROOT, "JSON encode: %.2f µs per message (best of 5), %.2f %% of one core at 1,600 messages/s%n",
            nsPerMessage / 1e3, 100 * nsPerMessage * perSecond / 1e9);
        System.out.printf(Locale.ROOT, "JSON:   %.1f bytes per message, %.1f with the frame header, %.0f KB/s%n",
            (double) jsonBytes / n, (double) jsonFramed / n, jsonFramed / (double) n * perSecond / 1000);
        System.out.printf(Locale.ROOT, "binary: %.1f bytes per message, %.1f with the frame header, %.0f KB/s%n",
            (double) binaryBytes / n, (double) binaryFramed / n, binaryFramed / (double) n * perSecond / 1000);
        System.out.printf(Locale.ROOT, "(checksum %d)%n", sink);
    }

    private static long encodeAll(List<StreamMessage> messages, StringBuilder sb) {
        long chars = 0;
        for (StreamMessage m : messages) {
            sb.setLength(0);
            StreamCodec.encodeTo(sb, m);
            chars += sb.length();
        }
        return chars;
    }

    private static int frameHeader(int payload) {
        return payload < 126 ? 2 : 4;
    }

    /** The same content in a binary form: type and stream, timestamp, values, accuracy; the orientation's quaternion. */
    private static int binarySize(StreamMessage m) {
        if (m instanceof StreamMessage.Sample) return 1 + 8 + 4 * ((StreamMessage.Sample) m).getValues().length + 1;
        return 1 + 8 + 4 * 8;
    }

    private static List<StreamMessage> messages(int rounds) {
        SplittableRandom random = new SplittableRandom(24);
        List<StreamMessage> out = new ArrayList<>(rounds * 8);
        long t = 81_234_567_890_123L;
        for (int k = 0; k < rounds; k++) {
            t += 5_000_000L + random.nextInt(20_000);
            int i = 0;
            for (SessionStream s : STREAMS) {
                float[] v = new float[s.getValueCount()];
                for (int j = 0; j < v.length; j++) v[j] = value(s, j, random);
                out.add(new StreamMessage.Sample(s, t + i++ * 137, v, 3));
            }
            double w = random.nextDouble(-1, 1), x = random.nextDouble(-1, 1), y = random.nextDouble(-1, 1), z = random.nextDouble(-1, 1);
            double norm = Math.sqrt(w * w + x * x + y * y + z * z);
            out.add(new StreamMessage.Orientation(t + 999, w / norm, x / norm, y / norm, z / norm));
        }
        return out;
    }

    /** A reading as a phone gives it: gravity and noise in m/s², small rates in rad/s, the field in µT, unit-quaternion parts. */
    private static float value(SessionStream s, int j, SplittableRandom r) {
        switch (s) {
            case ACCELEROMETER: return (float) ((j == 2 ? 9.80665 : 0.0) + r.nextGaussian() * 0.05);
            case GYROSCOPE:
            case GYROSCOPE_UNCALIBRATED: return (float) (r.nextGaussian() * 0.02);
            case MAGNETOMETER:
            case MAGNETOMETER_UNCALIBRATED: return (float) ((j == 1 ? 20.0 : j == 2 ? -40.0 : 0.0) + r.nextGaussian() * 0.5);
            default: return (float) r.nextDouble(-1, 1);
        }
    }
}
