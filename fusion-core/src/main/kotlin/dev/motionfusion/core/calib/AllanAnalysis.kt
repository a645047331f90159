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
        val rate = gyroscope?.rateHz ?: accelerometer?.rateHz ?: Double.NaN
        appendLine("# IMU noise model from the Allan deviation of a still recording (overlapping ADEV).")
        appendLine("# Made by $source.")
        appendLine("# The four keys are CONTINUOUS-TIME figures, as kalibr defines them: noise densities in")
        appendLine("# unit/sqrt(Hz), random walks in unit/s/sqrt(Hz); they do not depend on the sample rate.")
        appendLine("# The discrete-time figures in the comments are per sample at update_rate f = ${num(rate)} Hz")
        appendLine("# (dt = 1/f = ${num(1.0 / rate)} s): white noise sigma_d = noise_density * sqrt(f), the standard")
        appendLine("# deviation of one sample's noise; bias random walk sigma_bd = random_walk / sqrt(f), the standard")
        appendLine("# deviation of the bias change from one sample to the next (kalibr's IMU noise model).")
        section("Accelerometers", "accelerometer", accelerometer, accelerometerTerms, "m/s^2", rate)
        section("Gyroscopes", "gyroscope", gyroscope, gyroscopeTerms, "rad/s", rate)
        appendLine("rostopic: /imu0")
        appendLine("update_rate: ${num(rate)}  # Hz, mean sample rate of the ${if (gyroscope != null) "gyroscope" else "accelerometer"}")
    }

    private fun StringBuilder.section(title: String, key: String, curve: AllanCurve?, terms: List<NoiseTerms>?, unit: String, rate: Double) {
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
        appendLine("# ${key} discrete at ${num(rate)} Hz: white noise sigma_d ${num(DiscreteNoise.white(n, rate))} $unit, " +
            "bias random walk sigma_bd ${num(DiscreteNoise.randomWalk(largest(walks), rate))} $unit per sample")
        appendLine("# ${key} bias instability ($unit): ${terms.joinToString(" ") { num(it.biasInstability) }} at tau ${terms.joinToString(" ") { num(it.biasInstabilityTau) }} s")
        appendLine("# ${curve.samples} samples at ${num(curve.rateHz)} Hz, ${curve.gaps} gaps")
    }

    /** The largest finite value, NaN when none is. */
    private fun largest(values: List<Double>): Double = values.filter { it.isFinite() }.maxOrNull() ?: Double.NaN

    private fun num(v: Double): String = yamlNumber(v)

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

/**
 * The continuous-time IMU noise figures of kalibr's model turned into discrete-time ones at a
 * sample rate f (Δt = 1/f), as kalibr's IMU noise model defines them.
 */
public object DiscreteNoise {
    /** White noise: σd = σc / √Δt = σc·√f, the standard deviation of one sample's noise (unit), from the density σc (unit/√Hz). */
    @JvmStatic
    public fun white(density: Double, rateHz: Double): Double = density * kotlin.math.sqrt(rateHz)

    /** Bias random walk: σbd = σb·√Δt = σb / √f, the standard deviation of the bias change between two samples (unit), from σb (unit/s/√Hz). */
    @JvmStatic
    public fun randomWalk(walk: Double, rateHz: Double): Double = walk / kotlin.math.sqrt(rateHz)
}

/** Six significant digits without trailing zeros; YAML's .nan for unknown (the noise files' numbers, here and in export). */
internal fun yamlNumber(v: Double): String {
    if (!v.isFinite()) return ".nan"
    val s = String.format(Locale.ROOT, "%.6g", v)
    val e = s.indexOfAny(charArrayOf('e', 'E'))
    val mantissa = if (e < 0) s else s.substring(0, e)
    val trimmed = if ('.' in mantissa) mantissa.trimEnd('0').trimEnd('.') else mantissa
    return if (e < 0) trimmed else trimmed + s.substring(e)
}
