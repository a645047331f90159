package dev.motionfusion.core.input

import dev.motionfusion.core.eval.StillTilt
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.replay.ErrorStatistics
import dev.motionfusion.core.replay.OrientationComparison
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.event.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import java.util.Locale
import kotlin.math.acos
import kotlin.math.sqrt

/**
 * The importers on the real phyphox and Sensor Logger exports of ../shared/data/realdata (public
 * repositories, see its SOURCES.md; never copied into this one). Each input either replays upright
 * (its 1 s mean accelerometer readings and the phone's own orientation, where the export has
 * one, agree with the filter's) or fails with the documented message. The tilt at still samples
 * is reported here and compared with VQF's by eval.PeerRelativeTest.
 */
class RealExportsTest {
    private val root: Path = Paths.get("../shared/data/realdata").let { if (Files.isDirectory(it)) it else Paths.get("../../shared/data/realdata") }

    /**
     * An input (relative to the data folder) and what must happen: null replays, [LOW_RATE] replays
     * but is sampled too slowly (5–10 Hz) for the gyroscope to follow its motion, so its tilt is
     * reported and not asserted; else a fragment of the error.
     */
    private val cases = CASES

    private class Outcome(val stillSamples: Int, val tilt: ErrorStatistics, val windows: ErrorStatistics, val vsPhone: ErrorStatistics?, val headingVsPhone: ErrorStatistics?, val rows: Long)

    /** Replays [rec]; the tilt error is [StillTilt]'s: the filter's "up" in the device frame against the accelerometer's, at still samples. */
    private fun replay(rec: Recording, settings: FilterSettings = FilterSettings()): Outcome {
        val tilt = StillTilt()
        val phone = if (SessionStream.ROTATION_VECTOR in rec.streams) OrientationComparison { _, _, _, _ -> } else null
        var rows = 0L
        // Over 1 s windows: the mean accelerometer reading against the mean of the filter's "up"
        // (both in the device frame): motion averages out, an upside-down filter does not.
        val windows = ErrorStatistics()
        val sumA = DoubleArray(3)
        val sumUp = DoubleArray(3)
        var windowStart = Double.NaN
        val listener = object : ReplayListener {
            override fun step(step: ReplayStep) {
                rows++
                tilt.add(step.timeS, step.angularVelocity, step.specificForce, step.orientation)
                if (!step.initialised) return
                phone?.estimate(step.timestampNs, step.orientation)
                val a = step.specificForce
                val q = step.orientation
                val n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
                val up = doubleArrayOf(2 * (q[1] * q[3] - q[0] * q[2]), 2 * (q[2] * q[3] + q[0] * q[1]), 1 - 2 * (q[1] * q[1] + q[2] * q[2]))
                if (n.isFinite()) for (k in 0 until 3) { sumA[k] += a[k]; sumUp[k] += up[k] }
                if (windowStart.isNaN()) windowStart = step.timeS
                if (step.timeS - windowStart >= 1.0) {
                    val na = sqrt(sumA.sumOf { it * it })
                    val nu = sqrt(sumUp.sumOf { it * it })
                    if (na > 0 && nu > 0) windows.add(Math.toDegrees(acos(((0 until 3).sumOf { sumA[it] * sumUp[it] } / (na * nu)).coerceIn(-1.0, 1.0))))
                    sumA.fill(0.0); sumUp.fill(0.0)
                    windowStart = step.timeS
                }
            }

            override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) {
                if (stream == SessionStream.ROTATION_VECTOR) phone?.reference(timestampNs, values[3], values[0], values[1], values[2])
            }
        }
        rec.events().use { Replayer(settings).run(it, rec.originNs, listener) }
        return Outcome(tilt.still.count.toInt(), tilt.still, windows, phone?.inclination, phone?.heading, rows)
    }

    @Test
    fun `every real export replays upright or fails with its documented message`() {
        assumeTrue(Files.isDirectory(root), "no ../shared/data/realdata beside the repository: real exports not tested")
        val table = StringBuilder("| input | format | result | still samples | tilt vs accelerometer when still, 6D, median / p95 (°) | same, 9D | tilt vs 1 s mean of the accelerometer, 6D, median (°) | inclination vs phone's orientation, median (°) | heading vs phone's orientation, 9D, median (°) |\n|---|---|---|---|---|---|---|---|---|\n")
        val failures = ArrayList<String>()
        for ((input, expected) in cases) {
            val path = root.resolve(input)
            if (!Files.exists(path)) {
                failures += "$input: not in ../shared/data/realdata (a case of this test must exist there)"
                continue
            }
            try {
                Recording.open(path).use { rec ->
                    // The tilt at still samples is compared with VQF's by PeerRelativeTest (defaults);
                    // here it is reported, 6D and 9D beside.
                    val o = replay(rec, FilterSettings(mode = FilterMode.IMU))
                    val nineD = if (SessionStream.MAGNETOMETER in rec.streams) replay(rec) else null
                    val nine = nineD?.tilt?.let { "${f(it.percentile(0.5))} / ${f(it.percentile(0.95))}" } ?: "—"
                    val vs = o.vsPhone?.let { f(it.percentile(0.5)) } ?: "—"
                    val headingVs = nineD?.headingVsPhone?.let { f(it.percentile(0.5)) } ?: "—"
                    table.append("| $input | ${rec.format.description} | replays, ${o.rows} rows (${rec.streams.joinToString(" ") { it.key }})${rec.notes.joinToString("") { "; note: $it" }} | ${o.stillSamples} | ${f(o.tilt.percentile(0.5))} / ${f(o.tilt.percentile(0.95))} | $nine | ${f(o.windows.percentile(0.5))} | $vs | $headingVs |\n")
                    if (expected != null && expected != LOW_RATE) failures += "$input: replayed, expected an error with '$expected'"
                    if (expected != LOW_RATE && !(o.windows.percentile(0.5) < 10.0)) failures += "$input: tilt disagrees with the accelerometer's 1 s means by ${o.windows.percentile(0.5)}° (median)"
                    if (o.vsPhone != null && !(o.vsPhone.percentile(0.5) < 10.0)) failures += "$input: inclination differs from the phone's orientation by ${o.vsPhone.percentile(0.5)}° (median)"
                    // The phone's heading (iOS: true north; the filter: magnetic north) within the declination and the filter's own error.
                    // Where the phone's heading follows a field it left an offset in (PHONE_FIELD_OFFSET), the filter takes the field as read.
                    val headingCheck = if (input in PHONE_FIELD_OFFSET && nineD != null) replay(rec, FilterSettings(hardIronThreshold = null)) else nineD
                    if (headingCheck?.headingVsPhone != null && !(headingCheck.headingVsPhone.percentile(0.5) < 20.0)) failures += "$input: heading differs from the phone's orientation by ${headingCheck.headingVsPhone.percentile(0.5)}° (median, 9D)"
                    if (o.rows == 0L) failures += "$input: no rows"
                }
            } catch (e: DataFormatException) {
                table.append("| $input | | error: ${e.reason.replace("|", "/")} | | | | | | |\n")
                if (expected == null || expected == LOW_RATE || !e.message!!.contains(expected)) failures += "$input: ${e.message}, expected ${expected ?: "a replay"}"
            }
        }
        println(table)
        Files.createDirectories(Paths.get("target"))
        Files.write(Paths.get("target/realdata-table.md"), table.toString().toByteArray())
        assertTrue(failures.isEmpty(), failures.joinToString("\n"))
        assertEquals(cases.size, table.lines().count { it.startsWith("| ") } - 1)
    }

    internal companion object {
        internal val CASES: List<Pair<String, String?>> = listOf(
            "pp-accmag-bb301974" to "without gyroscope data",
            "pp-android-albabernal" to "without accelerometer data",
            "pp-android-azzipp" to "without accelerometer data",
            "pp-android-montpelllier" to LOW_RATE, // decimated to 10 Hz by its author, on a bicycle
            "pp-android-soerenarlt" to null,
            "pp-android-wld16" to "holds 2 recordings",
            "pp-android-wld16/studies/data_science/res/phybox_data" to null,
            "pp-android-wld16/studies/data_science/res/phybox_data_2" to null,
            "pp-degs-adtngrha" to null,
            "pp-ios-foger3" to null,
            "pp-ios-kartof0nix" to "belongs to another recording",
            "pp-ios-slmaking" to null,
            "pp-nounits-shantanu" to "holds 2 recordings",
            "pp-nounits-shantanu/Data/bus_to_home" to LOW_RATE, // a 5 Hz custom experiment
            "pp-nounits-shantanu/Data/bus_to_home.zip" to LOW_RATE,
            "pp-tab-ganesh" to "without accelerometer data",
            "pp-tab-ganesh/Gyroscope.csv" to "without accelerometer data",
            "sl-android-anurag" to null,
            "sl-android-igor" to "holds 2 recordings",
            "sl-android-igor/1" to null,
            "sl-android-igor/bom" to null,
            "sl-android-malimszen/2023-11-24_07-25-54.zip" to "without Gyroscope.csv",
            "sl-android-santollan" to null,
            "sl-ios-bennyjhui" to "WITHOUT gravity",
            "sl-ios-lynch" to "holds 5 recordings",
            "sl-ios-lynch/data/2022-09-09_13-14-55" to "without Gyroscope.csv",
            "sl-ios-lynch/data/2022-09-09_13-14-55.zip" to "without Gyroscope.csv",
            "sl-ios-lynch/data/2022-09-16_11-15-46" to null,
            "sl-ios-lynch/data/2022-09-16_11-15-46.zip" to null,
            "sl-ios-lynch/data/2022-09-26_15-32-56.zip" to null,
            "sl-ios-siberiawolf" to null,
            "sl-ios-simorxb" to null,
            "sl-unknown-shuhrat" to null,
        )

        const val LOW_RATE = "(replays, too slowly sampled to check)"

        /**
         * Exports whose own orientation follows a calibrated field that still holds an offset, so its heading is no
         * reference for the filter's with its hard-iron estimate: the filter takes 13 µT off sl-ios-siberiawolf's
         * field, whose dip then comes nearer the earth's there (calib/RealMagnetometerTest). The table reports the
         * defaults' heading; the check compares the phone's with the filter's on the field as read.
         */
        val PHONE_FIELD_OFFSET = setOf("sl-ios-siberiawolf")
    }

    private fun f(v: Double) = String.format(Locale.ROOT, "%.1f", v)
}
