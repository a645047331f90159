package dev.motionfusion.core.calib

import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import kotlin.math.abs
import kotlin.math.asin
import kotlin.math.sqrt

/**
 * The magnetometer fit on the real exports with an uncalibrated magnetometer (SOURCES.md of
 * ../shared/data/realdata: two iPhone Sensor Logger exports, whose MagnetometerUncalibrated.csv
 * has no bias columns), read through the project's import code. Skipped when the data is absent.
 */
class RealMagnetometerTest {
    private val realdata: Path? = listOf("../shared/data/realdata", "../../shared/data/realdata").map { Paths.get(it) }.firstOrNull { Files.isDirectory(it) }

    private fun folder(relative: String): Path {
        assumeTrue(realdata != null, "../shared/data/realdata is absent: real-data test skipped")
        val dir = realdata!!.resolve(relative)
        assumeTrue(Files.isDirectory(dir), "$dir is absent: real-data test skipped")
        return dir
    }

    @Test
    fun `an export of only uncalibrated streams, turned through many orientations, is fitted and its field narrows`() {
        // The export holds only the uncalibrated streams; the importer reads them as they are.
        val fitter = MagnetometerFitter(CalibrationSettings(), SessionStream.MAGNETOMETER_UNCALIBRATED)
        Recording.open(folder("sl-ios-simorxb")).use { rec ->
            assertTrue(SessionStream.MAGNETOMETER_UNCALIBRATED in rec.streams, "streams ${rec.streams}")
            rec.events(setOf(SessionStream.MAGNETOMETER_UNCALIBRATED)).use { e ->
                while (e.next()) fitter.add(e.values[0], e.values[1], e.values[2])
            }
        }
        val fit = fitter.fit()
        println("sl-ios-simorxb: $fit")
        val m = (fit as? Fit.Done)?.value ?: throw AssertionError("refused: $fit")
        println("sl-ios-simorxb: %d samples, coverage %.2f, offset %s µT, field %.1f µT, residual %.2f µT; |B| std %.2f → %.2f µT"
            .format(m.samples, m.coverage, m.correction.offset, m.fieldStrength, m.residualRms, m.magnitudeStdBefore, m.magnitudeStdAfter))
        assertTrue(m.magnitudeStdAfter < 0.25 * m.magnitudeStdBefore, "std ${m.magnitudeStdBefore} → ${m.magnitudeStdAfter}")
        assertTrue(m.fieldStrength in 25.0..70.0, "field ${m.fieldStrength} µT")
    }

    @Test
    fun `a recording that tilts the phone only a little is refused, and the phone's own calibration is compared`() {
        val dir = folder("sl-ios-siberiawolf/datasets/gaming/2023-06-11_01-01-00")
        Recording.open(dir).use { rec ->
            assertTrue(SessionStream.MAGNETOMETER_UNCALIBRATED in rec.streams, "streams ${rec.streams}")
            val cal = rec.events().use { Calibrator.calibrate(it, rec.streams) }
            println("sl-ios-siberiawolf: ${cal.refused}")
            assertTrue(cal.magnetometer == null && "directions" in cal.refused["magnetometer"].orEmpty(), "${cal.magnetometer} ${cal.refused}")
            // The phone's own hard-iron estimate: raw minus calibrated field, and the spread of both.
            val raw = Moments()
            val phone = Moments()
            val offset = Array(3) { Moments() }
            val lastRaw = DoubleArray(3) { Double.NaN }
            rec.events(setOf(SessionStream.MAGNETOMETER_UNCALIBRATED, SessionStream.MAGNETOMETER)).use { e ->
                while (e.next()) {
                    val v = e.values
                    val norm = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                    if (e.stream == SessionStream.MAGNETOMETER_UNCALIBRATED) {
                        raw.add(norm); v.copyInto(lastRaw, 0, 0, 3)
                    } else {
                        phone.add(norm)
                        if (!lastRaw[0].isNaN()) for (k in 0 until 3) offset[k].add(lastRaw[k] - v[k])
                    }
                }
            }
            println("sl-ios-siberiawolf: |B| std raw %.2f µT, phone-calibrated %.2f µT; phone's offset (%.1f, %.1f, %.1f) µT ± (%.1f, %.1f, %.1f)"
                .format(raw.std, phone.std, offset[0].mean, offset[1].mean, offset[2].mean, offset[0].std, offset[1].std, offset[2].std))
            assertTrue(phone.std < raw.std)
        }
    }

    /**
     * iOS's calibrated field in this export keeps an offset of its own: the filter's hard-iron estimate
     * (HardIronEstimate, from the field's turning against the gyroscope) takes off about 13 µT, and the field's
     * dip against the accelerometer then reads 65° where iOS's field reads 78°. The export's Location.csv puts it
     * at 52.35° N, 4.92° E, where the earth's field dips about 67° (WMM), and the dip spreads less (2.8° → 1.6°).
     * The filter's heading is 25° from the phone's own orientation here, consistent with that offset
     * (RealExportsTest checks the phone's heading against the filter's on the field as read).
     */
    @Test
    fun `the hard-iron estimate steadies the dip of a field iOS calibrated`() {
        val dir = folder("sl-ios-siberiawolf/datasets/gaming/2023-06-11_01-01-00")
        val a = ArrayList<DoubleArray>()
        val m = ArrayList<DoubleArray>()
        val replayer = Replayer(FilterSettings())
        Recording.open(dir).use { rec ->
            rec.events().use {
                replayer.run(it, rec.originNs, object : ReplayListener {
                    override fun step(step: ReplayStep) {
                        if (step.specificForce.all { v -> v.isFinite() } && step.magneticField.all { v -> v.isFinite() }) {
                            a += step.specificForce.copyOf(); m += step.magneticField.copyOf()
                        }
                    }
                })
            }
        }
        val offset = replayer.filter.diagnostics().magnetometerOffset
        fun dips(ox: Double, oy: Double, oz: Double): Moments {
            val dip = Moments()
            for (i in a.indices) {
                val (ax, ay, az) = a[i]
                val mx = m[i][0] - ox
                val my = m[i][1] - oy
                val mz = m[i][2] - oz
                val c = (ax * mx + ay * my + az * mz) / (sqrt(ax * ax + ay * ay + az * az) * sqrt(mx * mx + my * my + mz * mz))
                dip.add(Math.toDegrees(asin(c.coerceIn(-1.0, 1.0))))
            }
            return dip
        }
        val phone = dips(0.0, 0.0, 0.0)
        val taken = dips(offset.x, offset.y, offset.z)
        println("sl-ios-siberiawolf: offset taken off (%.1f, %.1f, %.1f) µT; dip %.1f° ± %.2f° as iOS calibrated it, %.1f° ± %.2f° with the offset off"
            .format(offset.x, offset.y, offset.z, phone.mean, phone.std, taken.mean, taken.std))
        assertTrue(a.size > 3000, "${a.size} steps")
        assertTrue(offset.norm() > 5.0, "offset $offset")
        assertTrue(taken.std < 0.7 * phone.std, "dip spread ${phone.std}° → ${taken.std}°")
        // The dip is measured against the specific force (up), so it reads negative; the earth's there is 67° down.
        assertTrue(abs(-taken.mean - EARTH_DIP_DEG) < abs(-phone.mean - EARTH_DIP_DEG) - 5.0, "dip ${phone.mean}° → ${taken.mean}°, the earth's $EARTH_DIP_DEG°")
    }

    @Test
    fun `the gyroscope bias from still periods of a real recording agrees with the phone's own`() {
        val dir = folder("sl-ios-siberiawolf/datasets/gaming/2023-06-11_01-01-00")
        Recording.open(dir).use { rec ->
            val cal = rec.events().use { Calibrator.calibrate(it, rec.streams) }
            val g = cal.gyroscope ?: throw AssertionError("refused: ${cal.refused}")
            assertTrue(g.stream == SessionStream.GYROSCOPE_UNCALIBRATED)
            // The phone's bias: uncalibrated minus calibrated rate, at the calibrated sample nearest in time (both about 100 Hz).
            val phone = Array(3) { Moments() }
            val lastRaw = DoubleArray(3) { Double.NaN }
            var lastRawNs = Long.MIN_VALUE
            rec.events(setOf(SessionStream.GYROSCOPE_UNCALIBRATED, SessionStream.GYROSCOPE)).use { e ->
                while (e.next()) {
                    if (e.stream == SessionStream.GYROSCOPE_UNCALIBRATED) {
                        e.values.copyInto(lastRaw, 0, 0, 3); lastRawNs = e.timestampNs
                    } else if (lastRawNs != Long.MIN_VALUE && e.timestampNs - lastRawNs < 5_000_000L) {
                        for (k in 0 until 3) phone[k].add(lastRaw[k] - e.values[k])
                    }
                }
            }
            println("sl-ios-siberiawolf gyroscope: bias %s ± %s rad/s over %.1f s still; the phone's (%.6f, %.6f, %.6f) rad/s"
                .format(g.bias, g.biasStdError, g.stillTimeS, phone[0].mean, phone[1].mean, phone[2].mean))
            for (k in 0 until 3) {
                val d = kotlin.math.abs(g.bias[k] - phone[k].mean)
                assertTrue(d < 3 * g.biasStdError[k] + 2e-4, "axis $k: ours ${g.bias[k]}, the phone's ${phone[k].mean}")
            }
        }
    }

    private companion object {
        /** The earth's field's dip at the export's Location.csv (52.35° N, 4.92° E) in 2023, WMM2020, degrees. */
        const val EARTH_DIP_DEG = 67.0
    }
}
