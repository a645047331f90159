/*
 * Noise characterisation of a still recording: the Allan deviation of the gyroscope (preferring
 * the uncalibrated stream, whose bias Android does not adjust) and of the accelerometer, their
 * noise terms, and the IMU noise file in the layout of kalibr's imu.yaml.
 * Units: rad/s and m/s²; densities per √Hz; device frame.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import java.util.Locale

/** The Allan curves of a recording ([gyroscope], [accelerometer] null when absent) and their noise terms. */
public class AllanResult(
    public val gyroscope: AllanCurve?,
    public val gyroscopeStream: SessionStream?,
    public val accelerometer: AllanCurve?,
) {
    public val gyroscopeTerms: List<NoiseTerms>? = gyroscope?.fits()
    public val accelerometerTerms: List<NoiseTerms>? = accelerometer?.fits()

    /**
     * The noise figures as kalibr's IMU configuration reads them: per quantity the largest of
     * the three axes (the conservative choice for a filter); per-axis values and the bias
     * instability in comments. A random walk the recording is too short to show is written as
     * its upper bound, and the comment says so.
     */
    public fun kalibrYaml(source: String): String = buildString {
        appendLine("# IMU noise model from the Allan deviation of a still recording (overlapping ADEV).")
        appendLine("# Made by $source. Noise densities in unit/sqrt(Hz), random walks in unit/s/sqrt(Hz).")
        section("Accelerometers", "accelerometer", accelerometer, accelerometerTerms, "m/s^2")
        section("Gyroscopes", "gyroscope", gyroscope, gyroscopeTerms, "rad/s")
        val rate = gyroscope?.rateHz ?: accelerometer?.rateHz ?: Double.NaN
        appendLine("rostopic: /imu0")
        appendLine("update_rate: ${num(rate)}  # Hz, mean sample rate of the ${if (gyroscope != null) "gyroscope" else "accelerometer"}")
    }

    private fun StringBuilder.section(title: String, key: String, curve: AllanCurve?, terms: List<NoiseTerms>?, unit: String) {
        appendLine("#$title")
        if (curve == null || terms == null) {
            appendLine("# no $key stream in the recording")
            return
        }
        val n = largest(terms.map { it.whiteNoise })
        val walks = terms.map { if (it.randomWalk.isFinite()) it.randomWalk else it.randomWalkUpperBound }
        val bounded = terms.any { !it.randomWalk.isFinite() }
        appendLine("${key}_noise_density: ${num(n)}  # $unit/sqrt(Hz); x y z: ${terms.joinToString(" ") { num(it.whiteNoise) }}")
        appendLine("${key}_random_walk: ${num(largest(walks))}  # $unit/s/sqrt(Hz); x y z: ${walks.joinToString(" ") { num(it) }}" +
            if (bounded) " (upper bound: the recording is too short to show the random walk on every axis)" else "")
        appendLine("# ${key} bias instability ($unit): ${terms.joinToString(" ") { num(it.biasInstability) }} at tau ${terms.joinToString(" ") { num(it.biasInstabilityTau) }} s")
        appendLine("# ${curve.samples} samples at ${num(curve.rateHz)} Hz, ${curve.gaps} gaps")
    }

    /** The largest finite value, NaN when none is. */
    private fun largest(values: List<Double>): Double = values.filter { it.isFinite() }.maxOrNull() ?: Double.NaN

    /** Six significant digits without trailing zeros; YAML's .nan for unknown. */
    private fun num(v: Double): String {
        if (!v.isFinite()) return ".nan"
        val s = String.format(Locale.ROOT, "%.6g", v)
        val e = s.indexOfAny(charArrayOf('e', 'E'))
        val mantissa = if (e < 0) s else s.substring(0, e)
        val trimmed = if ('.' in mantissa) mantissa.trimEnd('0').trimEnd('.') else mantissa
        return if (e < 0) trimmed else trimmed + s.substring(e)
    }

    public companion object {
        /** Reads [events] (a recording with [streams]) once. [progress] as in [Calibrator.calibrate]. */
        @JvmStatic
        @JvmOverloads
        public fun run(events: SensorEvents, streams: Set<SessionStream>, progress: ((Long) -> Unit)? = null): AllanResult {
            val gyroStream = Calibrator.gyroscopeStream(streams)
            val gyro = gyroStream?.let { AllanAccumulator() }
            val acc = if (SessionStream.ACCELEROMETER in streams) AllanAccumulator() else null
            events.forEachEvent(progress) { stream, t, v ->
                when (stream) {
                    gyroStream -> gyro?.add(t, v[0], v[1], v[2])
                    SessionStream.ACCELEROMETER -> acc?.add(t, v[0], v[1], v[2])
                    else -> Unit
                }
            }
            return AllanResult(gyro?.takeIf { it.samples > 0 }?.curve(), gyroStream, acc?.takeIf { it.samples > 0 }?.curve())
        }
    }
}
