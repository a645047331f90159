package dev.motionfusion.core.input

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.replay.ErrorStatistics
import dev.motionfusion.core.replay.OrientationComparison
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.session.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import java.util.Locale
import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.sqrt

/**
 * The importers on the real phyphox and Sensor Logger exports of ../shared/data/realdata (public
 * repositories, see its SOURCES.md; never copied into this one). Each input either replays with
 * a tilt that agrees with its own accelerometer whenever the phone is still (and with the
 * phone's own orientation where the export has one), or fails with the documented message.
 */
class RealExportsTest {
    private val root: Path = Paths.get("../shared/data/realdata").let { if (Files.isDirectory(it)) it else Paths.get("../../shared/data/realdata") }

    /** An input (relative to the data folder) and what must happen: null replays, else a fragment of the error. */
    private val cases: List<Pair<String, String?>> = listOf(
        "pp-accmag-bb301974" to "without gyroscope data",
        "pp-android-albabernal" to "without accelerometer data",
        "pp-android-azzipp" to "without accelerometer data",
        "pp-android-montpelllier" to null,
        "pp-android-soerenarlt" to null,
        "pp-android-wld16" to "holds 2 recordings",
        "pp-android-wld16/studies/data_science/res/phybox_data" to null,
        "pp-android-wld16/studies/data_science/res/phybox_data_2" to null,
        "pp-degs-adtngrha" to null,
        "pp-ios-foger3" to null,
        "pp-ios-kartof0nix" to null,
        "pp-ios-slmaking" to null,
        "pp-nounits-shantanu" to "holds 2 recordings",
        "pp-nounits-shantanu/Data/bus_to_home" to null,
        "pp-nounits-shantanu/Data/bus_to_home.zip" to null,
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

    private class Outcome(val stillSamples: Int, val tilt: ErrorStatistics, val vsPhone: ErrorStatistics?, val rows: Long)

    /** Replays [rec]; the tilt error is the angle between the filter's "up" in the device frame and the accelerometer's, at still samples. */
    private fun replay(rec: Recording): Outcome {
        val tilt = ErrorStatistics()
        val phone = if (SessionStream.ROTATION_VECTOR in rec.streams) OrientationComparison { _, _, _, _ -> } else null
        var rows = 0L
        var firstT = Double.NaN
        var still = 0
        val listener = object : ReplayListener {
            override fun step(step: ReplayStep) {
                rows++
                if (!step.initialised) return
                if (firstT.isNaN()) firstT = step.timeS
                phone?.estimate(step.timestampNs, step.orientation)
                val a = step.specificForce
                val n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
                // Still: the accelerometer reads gravity alone; skip the first 2 s while the filter settles.
                if (abs(n - STANDARD_GRAVITY) > 0.1 || step.timeS - firstT < 2.0) return
                val (w, x, y, z) = step.orientation.toList()
                // The world's up (ENU z) in the device frame: the third row of R(q).
                val ux = 2 * (x * z - w * y)
                val uy = 2 * (y * z + w * x)
                val uz = 1 - 2 * (x * x + y * y)
                val c = (ux * a[0] + uy * a[1] + uz * a[2]) / n
                tilt.add(Math.toDegrees(acos(c.coerceIn(-1.0, 1.0))))
                still++
            }

            override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) {
                if (stream == SessionStream.ROTATION_VECTOR) phone?.reference(timestampNs, values[3], values[0], values[1], values[2])
            }
        }
        rec.events().use { Replayer().run(it, rec.originNs, listener) }
        return Outcome(still, tilt, phone?.inclination, rows)
    }

    @Test
    fun `every real export replays upright or fails with its documented message`() {
        assumeTrue(Files.isDirectory(root), "no ../shared/data/realdata beside the repository: real exports not tested")
        val table = StringBuilder("| input | format | result | still samples | tilt vs accelerometer, median / p95 (°) | inclination vs phone's orientation, median (°) |\n|---|---|---|---|---|---|\n")
        val failures = ArrayList<String>()
        for ((input, expected) in cases) {
            val path = root.resolve(input)
            assumeTrue(Files.exists(path), "$path missing")
            try {
                Recording.open(path).use { rec ->
                    val o = replay(rec)
                    val vs = o.vsPhone?.let { f(it.percentile(0.5)) } ?: "—"
                    table.append("| $input | ${rec.format.description} | replays, ${o.rows} rows (${rec.streams.joinToString(" ") { it.key }})${rec.notes.joinToString("") { "; note: $it" }} | ${o.stillSamples} | ${f(o.tilt.percentile(0.5))} / ${f(o.tilt.percentile(0.95))} | $vs |\n")
                    if (expected != null) failures += "$input: replayed, expected an error with '$expected'"
                    if (o.stillSamples > 0 && !(o.tilt.percentile(0.5) < 5.0)) failures += "$input: tilt disagrees with the accelerometer by ${o.tilt.percentile(0.5)}° (median)"
                    if (o.vsPhone != null && !(o.vsPhone.percentile(0.5) < 10.0)) failures += "$input: inclination differs from the phone's orientation by ${o.vsPhone.percentile(0.5)}° (median)"
                    if (o.rows == 0L) failures += "$input: no rows"
                }
            } catch (e: DataFormatException) {
                table.append("| $input | | error: ${e.reason.replace("|", "/")} | | | |\n")
                if (expected == null || !e.message!!.contains(expected)) failures += "$input: ${e.message}, expected ${expected ?: "a replay"}"
            }
        }
        println(table)
        Files.createDirectories(Paths.get("target"))
        Files.write(Paths.get("target/realdata-table.md"), table.toString().toByteArray())
        assertTrue(failures.isEmpty(), failures.joinToString("\n"))
        assertEquals(cases.size, table.lines().count { it.startsWith("| ") } - 1)
    }

    private fun f(v: Double) = String.format(Locale.ROOT, "%.1f", v)
}
