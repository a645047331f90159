/*
 * The plausibility probe every input passes through (Recording.events): the first samples of the
 * accelerometer, gyroscope and magnetometer are read once and their rate and typical magnitude
 * compared with what a phone can give (limits in filter/SensorRanges.kt, listed with the messages
 * in docs/IMPORT.md, "Plausibility"). An input that parses but cannot be right (times in another
 * unit, rows out of order, a stream in another unit) is an error saying which and how to fix it.
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.SensorRanges
import dev.motionfusion.core.io.DataFormatException
import java.util.Locale
import kotlin.math.sqrt

internal object Plausibility {
    /** Samples of each stream the probe reads. */
    const val PROBE_SAMPLES = 2000

    /** Events of all streams the probe reads at most (other streams may come first). */
    private const val MAX_PROBE_EVENTS = 40L * PROBE_SAMPLES

    private val PROBED = listOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER)

    /**
     * Reads the first [PROBE_SAMPLES] of each filter input of [events] (then closes it).
     * @throws DataFormatException naming [source] when the times or the magnitudes cannot be right.
     */
    fun check(source: String, format: RecordingFormat, present: Set<SessionStream>, events: SensorEvents) {
        val wanted = PROBED.filter { it in present }
        val times = PROBED.associateWith { LongArray(PROBE_SAMPLES) }
        val norms = PROBED.associateWith { DoubleArray(PROBE_SAMPLES) }
        val counts = IntArray(SessionStream.entries.size)
        var read = 0L
        events.use { e ->
            while (read++ < MAX_PROBE_EVENTS && e.next()) {
                val s = e.stream
                val t = times[s] ?: continue
                val i = counts[s.ordinal]
                if (i >= PROBE_SAMPLES) continue
                t[i] = e.timestampNs
                val v = e.values
                norms.getValue(s)[i] = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                counts[s.ordinal] = i + 1
                if (i + 1 == PROBE_SAMPLES && wanted.all { counts[it.ordinal] >= PROBE_SAMPLES }) break
            }
        }
        for (s in wanted) {
            val n = counts[s.ordinal]
            if (n < 2) continue
            checkTimes(source, format, s, times.getValue(s), n)
            checkMagnitudes(source, s, norms.getValue(s), n)
        }
    }

    private fun checkTimes(source: String, format: RecordingFormat, s: SessionStream, t: LongArray, n: Int) {
        val steps = DoubleArray(n - 1) { (t[it + 1] - t[it]).toDouble() }
        val notAdvancing = steps.count { it <= 0.0 }
        if (notAdvancing * 2 > steps.size) {
            val back = steps.count { it < 0.0 }
            val what = when {
                back * 2 > steps.size -> "step back (rows in reverse order?)"
                t.take(n).all { it == t[0] } -> "are all the same (${fmt(t[0] * 1e-9)} s)"
                else -> "do not advance"
            }
            fail(source, "${s.key}: ${notAdvancing} of the first ${steps.size} timestamp steps $what: " +
                "fewer than half the samples would be usable; sort the rows by time or give a time column that counts up")
        }
        val dt = median(steps.filter { it > 0.0 }.toDoubleArray())
        val rate = 1e9 / dt
        if (rate >= SensorRanges.MIN_RATE_HZ && rate <= SensorRanges.MAX_RATE_HZ) return
        val unit = timeUnit(format)
        val guess = listOf("ms" to 1e-3, "µs" to 1e-6, "ns" to 1e-9, "s" to 1.0, "min" to 60.0).map { (name, seconds) -> name to rate * unitSeconds(unit) / seconds }
            .firstOrNull { (name, r) -> name != unit && r >= 20.0 && r <= SensorRanges.MAX_RATE_HZ / 2 }
        val hint = if (guess != null) ": the times look like ${guess.first}, not $unit (that would be ${fmt(guess.second)} Hz); convert the time column to $unit" else
            ": an IMU samples at ${fmt(SensorRanges.MIN_RATE_HZ)}–${fmt(SensorRanges.MAX_RATE_HZ)} Hz; check the time column's unit ($unit), " +
                "or whether the recording was made that slowly (Sensor Logger's sampleRateMs in Metadata.csv)"
        fail(source, "${s.key}: the timestamps imply ${fmt(rate)} Hz$hint")
    }

    private fun checkMagnitudes(source: String, s: SessionStream, norm: DoubleArray, n: Int) {
        val m = median(norm.copyOf(n).filter { it.isFinite() }.toDoubleArray())
        if (m.isNaN()) return
        val message = when (s) {
            SessionStream.ACCELEROMETER -> when {
                m >= 0.5 && m <= 2.0 -> "looks like g, not m/s² (median |a| ${fmt(m)}; in m/s² a phone reads about ${fmt(STANDARD_GRAVITY)}): multiply the accelerometer by $STANDARD_GRAVITY"
                m < SensorRanges.MIN_MEDIAN_ACCELEROMETER_M_S2 -> "median |a| ${fmt(m)} m/s² is no accelerometer's (gravity alone is ${fmt(STANDARD_GRAVITY)}): a column of another quantity or unit (linear acceleration?)"
                m > SensorRanges.MAX_MEDIAN_ACCELEROMETER_M_S2 -> "median |a| ${fmt(m)} m/s² is over 3 g throughout: a column of another unit (cm/s² or mg?)"
                else -> null
            }
            SessionStream.GYROSCOPE ->
                if (m > SensorRanges.MAX_MEDIAN_GYROSCOPE_RAD_S) "median |ω| ${fmt(m)} rad/s: looks like °/s, not rad/s; multiply the gyroscope by π/180" else null
            SessionStream.MAGNETOMETER -> when {
                m == 0.0 -> "is zero throughout: no field was recorded; replay in 6D (--mode 6d) or leave the magnetometer out"
                m >= 0.1 && m <= 1.0 -> "looks like gauss, not µT (median |B| ${fmt(m)}; the earth's field is 25–65 µT): multiply the magnetometer by 100"
                m < SensorRanges.MIN_MEDIAN_MAGNETOMETER_UT -> "median |B| ${fmt(m)} µT is below any place's field (25–65 µT): a column of another unit, or replay in 6D (--mode 6d)"
                m >= 10_000.0 && m <= 100_000.0 -> "looks like nT, not µT (median |B| ${fmt(m)}; the earth's field is 25–65 µT): divide the magnetometer by 1000"
                m > SensorRanges.MAX_MEDIAN_MAGNETOMETER_UT -> "median |B| ${fmt(m)} µT is far above the earth's field (25–65 µT): a column of another unit, or replay in 6D (--mode 6d)"
                else -> null
            }
            else -> null
        } ?: return
        fail(source, "${s.key}: $message")
    }

    /** The unit the format's times are in, as its documentation states. */
    private fun timeUnit(format: RecordingFormat) = when (format) {
        RecordingFormat.IMU_TABLE, RecordingFormat.PHYPHOX -> "s"
        RecordingFormat.SESSION, RecordingFormat.SENSOR_LOGGER, RecordingFormat.EUROC, RecordingFormat.KALIBR -> "ns"
    }

    private fun unitSeconds(unit: String) = if (unit == "s") 1.0 else 1e-9

    private fun fail(source: String, reason: String): Nothing = throw DataFormatException(source, 0, 0, reason)

    private fun median(v: DoubleArray): Double {
        if (v.isEmpty()) return Double.NaN
        v.sort()
        return if (v.size % 2 == 1) v[v.size / 2] else 0.5 * (v[v.size / 2 - 1] + v[v.size / 2])
    }

    private fun fmt(v: Double): String = when {
        v == 0.0 -> "0"
        v >= 1e6 || v < 1e-3 -> String.format(Locale.ROOT, "%.3g", v)
        else -> java.math.BigDecimal(v).round(java.math.MathContext(3)).stripTrailingZeros().toPlainString()
    }
}
