package dev.motionfusion.core.input

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionArchive
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionWriter
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.io.TempDir
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.MethodSource
import java.io.ByteArrayOutputStream
import java.nio.file.Files
import java.nio.file.Path
import java.util.Random
import java.util.zip.GZIPOutputStream
import java.util.zip.ZipEntry
import java.util.zip.ZipOutputStream

/**
 * The same recording written in every input format fusion reads: each must yield the same
 * events (stream, time since the first event, values in SI and the Android convention).
 */
class InputFormatsTest {
    @TempDir
    lateinit var tmp: Path

    /** The recording: [n] instants 10 ms apart, accelerometer, gyroscope, magnetometer (float values, like SensorEvent). */
    private class Data(seed: Long, val n: Int = 60) {
        private val r = Random(seed)
        private fun v(scale: Double, offset: Double = 0.0) = (offset + scale * r.nextGaussian()).toFloat().toDouble()
        val acc = Array(n) { doubleArrayOf(v(0.5), v(0.5, 2.0), v(0.5, 9.5)) }
        val gyro = Array(n) { doubleArrayOf(v(0.2), v(0.2), v(0.2)) }
        val mag = Array(n) { doubleArrayOf(v(1.0, 5.0), v(1.0, 20.0), v(1.0, -40.0)) }
        fun timeS(k: Int) = "0.${"%02d".format(k)}".let { if (k >= 100) (k / 100.0).toString() else it }
    }

    private val data = Data(7)

    /** Expected events: per instant accelerometer, magnetometer (when [withMag]), gyroscope. */
    private fun expected(withMag: Boolean): List<Triple<SessionStream, Long, List<Double>>> = (0 until data.n).flatMap { k ->
        val t = k * 10_000_000L
        listOfNotNull(
            Triple(SessionStream.ACCELEROMETER, t, data.acc[k].toList()),
            if (withMag) Triple(SessionStream.MAGNETOMETER, t, data.mag[k].toList()) else null,
            Triple(SessionStream.GYROSCOPE, t, data.gyro[k].toList()),
        )
    }

    private fun read(path: Path, options: ImportOptions = ImportOptions()): List<Triple<SessionStream, Long, List<Double>>> =
        Recording.open(path, options).use { rec ->
            val out = ArrayList<Triple<SessionStream, Long, List<Double>>>()
            var first = Long.MIN_VALUE
            rec.events(setOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER)).use { e ->
                while (e.next()) {
                    if (first == Long.MIN_VALUE) first = e.timestampNs
                    out += Triple(e.stream, e.timestampNs - first, e.values.take(3))
                }
            }
            out
        }

    private fun zip(dir: Path, zipFile: Path, inFolder: Boolean): Path {
        ZipOutputStream(Files.newOutputStream(zipFile)).use { z ->
            Files.walk(dir).use { s -> s.filter { Files.isRegularFile(it) }.toList() }.sorted().forEach { f ->
                z.putNextEntry(ZipEntry((if (inFolder) "${dir.fileName}/" else "") + dir.relativize(f).toString().replace('\\', '/')))
                Files.copy(f, z)
                z.closeEntry()
            }
        }
        return zipFile
    }

    private fun gzip(text: String): ByteArray = ByteArrayOutputStream().also { o -> GZIPOutputStream(o).use { it.write(text.toByteArray()) } }.toByteArray()

    private fun write(dir: Path, name: String, text: String) {
        Files.createDirectories(dir)
        Files.write(dir.resolve(name), text.toByteArray())
    }

    private fun table(withMag: Boolean): String =
        (if (withMag) "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" else "t_s,gx,gy,gz,ax,ay,az\n") + (0 until data.n).joinToString("") { k ->
            (listOf(data.timeS(k)) + (data.gyro[k].toList() + data.acc[k].toList() + if (withMag) data.mag[k].toList() else emptyList()).map { it.toString() }).joinToString(",") + "\n"
        }

    /** One phyphox data set in [dialect]: separator and whether numbers use a decimal comma. */
    private fun phyphox(header: List<String>, rows: Array<DoubleArray>, sep: String, comma: Boolean, quoted: Boolean = true): String {
        fun num(x: Double) = x.toString().let { if (comma) it.replace('.', ',') else it }
        val h = header.joinToString(sep) { if (quoted) "\"$it\"" else it }
        return h + "\n" + (0 until data.n).joinToString("") { k -> (listOf(num(k * 0.01)) + rows[k].map(::num)).joinToString(sep) + "\n" }
    }

    private fun logger(rows: Array<DoubleArray>, scale: Double = 1.0): String =
        "time,seconds_elapsed,z,y,x\n" + (0 until data.n).joinToString("") { k ->
            "${1_700_000_000_000_000_000L + k * 10_000_000L},${k * 0.01},${rows[k][2] * scale},${rows[k][1] * scale},${rows[k][0] * scale}\n"
        }

    // Sessions store float values as their shortest decimal, the other formats as doubles: equal to 1e-7.

    /** Writes the recording as [format] under [tmp]; returns the path to open and the options. */
    private fun make(format: String): Pair<Path, ImportOptions> {
        val dir = tmp.resolve(format.replace(' ', '-'))
        val none = ImportOptions()
        return when (format) {
            "session folder", "session zip" -> {
                val s = tmp.resolve("session")
                if (!Files.exists(s)) {
                    SessionWriter.create(s, SessionMetadata(appVersion = "1", startAnchor = ClockAnchor(1L, 5_000L))).use { w ->
                        for (k in 0 until data.n) {
                            val t = 5_000L + k * 10_000_000L
                            val (a, g, m) = Triple(data.acc[k], data.gyro[k], data.mag[k])
                            w.accelerometer(t, a[0].toFloat(), a[1].toFloat(), a[2].toFloat(), 3)
                            w.magnetometer(t, m[0].toFloat(), m[1].toFloat(), m[2].toFloat(), 3)
                            w.gyroscope(t, g[0].toFloat(), g[1].toFloat(), g[2].toFloat(), 3)
                        }
                    }
                }
                (if (format == "session zip") tmp.resolve("session.zip").also { SessionArchive.zip(s, it) } else s) to none
            }
            "table" -> tmp.resolve("t.csv").also { Files.write(it, table(true).toByteArray()) } to none
            "table gz" -> tmp.resolve("t.csv.gz").also { Files.write(it, gzip(table(true))) } to none
            "trial" -> {
                write(dir, "input.csv", table(true))
                write(dir, "truth.csv", "t_s,qw,qx,qy,qz,movement\n" + (0 until data.n).joinToString("") { "${data.timeS(it)},1,0,0,0,1\n" })
                dir to none
            }
            else -> {
                when {
                    format.startsWith("phyphox android") || format.startsWith("phyphox ios") || format.startsWith("phyphox custom") -> {
                        val (sep, comma) = when {
                            format.contains("semicolon comma") -> ";" to true
                            format.contains("semicolon") -> ";" to false
                            format.contains("tab") -> "\t" to false
                            else -> "," to false
                        }
                        val ios = format.startsWith("phyphox ios")
                        val custom = format.startsWith("phyphox custom")
                        fun h(q: String, unit: String) = listOf(if (custom) "time" else "Time (s)") + "xyz".map { a ->
                            when {
                                ios -> "${a.uppercaseChar()} ($unit)"
                                custom -> "$q $a"
                                else -> "$q $a ($unit)"
                            }
                        }
                        // "copies": files renamed as a second export of the same experiment names them (iOS headers name no
                        // sensor, so the file's name must still tell it).
                        val copies = format.contains("copies")
                        write(dir, if (custom) "Acceleration.csv" else if (copies) "Accelerometer_2.csv" else "Accelerometer.csv", phyphox(h("Acceleration", "m/s^2"), data.acc, sep, comma))
                        write(dir, if (copies) "Gyroscope (1).csv" else "Gyroscope.csv", phyphox(h("Gyroscope", "rad/s"), data.gyro, sep, comma))
                        write(dir, if (copies) "Magnetometer 2.csv" else "Magnetometer.csv", phyphox(h("Magnetic field", "µT"), data.mag, sep, comma))
                        write(dir.resolve("meta"), "device.csv", "\"property\",\"value\"\n")
                    }
                    format.startsWith("sensor logger android") -> {
                        write(dir, "TotalAcceleration.csv", logger(data.acc))
                        write(dir, "Gyroscope.csv", logger(data.gyro))
                        write(dir, "Magnetometer.csv", logger(data.mag))
                        if (format.contains("with metadata")) write(dir, "Metadata.csv", "version,device name,platform,appVersion\n3,Pixel,android,1.28\n")
                    }
                    format.startsWith("sensor logger ios") && !format.contains("uncalibrated") -> {
                        // CoreMotion's convention: gravity and user acceleration with the opposite sign.
                        write(dir, "Gravity.csv", logger(data.acc, -1.0))
                        write(dir, "Accelerometer.csv", logger(Array(data.n) { DoubleArray(3) }))
                        write(dir, "Gyroscope.csv", logger(data.gyro))
                        write(dir, "Magnetometer.csv", logger(data.mag))
                        if (format.contains("with metadata")) write(dir, "Metadata.csv", "version,device name,recording time,platform,appVersion\n3,iPhone,x,ios,1.15\n")
                        if (format.endsWith("standardised")) {
                            write(dir, "Gravity.csv", logger(data.acc))
                            write(dir, "Metadata.csv", "version,device name,platform,appVersion,standardisation\n3,iPhone,ios,1.40,true\n")
                        }
                    }
                    format == "sensor logger ios uncalibrated only" -> {
                        write(dir, "AccelerometerUncalibrated.csv", logger(data.acc, -1.0 / STANDARD_GRAVITY))
                        write(dir, "GyroscopeUncalibrated.csv", logger(data.gyro))
                    }
                    else -> error(format)
                }
                val options = if (format == "sensor logger ios without metadata") ImportOptions(platform = Platform.IOS) else none
                (if (format.endsWith(" zip")) zip(dir, tmp.resolve("$format.zip".replace(' ', '-')), inFolder = true) else dir) to options
            }
        }
    }

    @ParameterizedTest(name = "{0}")
    @MethodSource("formats")
    fun `every format yields the same events`(format: String) {
        val (path, options) = make(format)
        val withMag = !format.contains("uncalibrated")
        val want = expected(withMag)
        val got = read(path, options)
        assertEquals(want.size, got.size, format)
        for (i in want.indices) {
            assertEquals(want[i].first, got[i].first, "$format event $i")
            assertEquals(want[i].second, got[i].second, "$format event $i time")
            for (k in 0 until 3) assertEquals(want[i].third[k], got[i].third[k], 1e-7 * (1 + kotlin.math.abs(want[i].third[k])), "$format event $i value $k")
        }
    }

    companion object {
        @JvmStatic
        fun formats(): List<String> = listOf(
            "session folder", "session zip", "table", "table gz", "trial",
            "phyphox android comma", "phyphox android semicolon", "phyphox android semicolon comma", "phyphox android tab", "phyphox android comma zip",
            "phyphox ios comma", "phyphox ios semicolon", "phyphox ios semicolon comma", "phyphox ios tab", "phyphox ios semicolon comma zip", "phyphox ios comma copies",
            "phyphox custom comma", "phyphox custom semicolon comma", "phyphox custom tab",
            "sensor logger android with metadata", "sensor logger android without metadata", "sensor logger android with metadata zip",
            "sensor logger ios with metadata", "sensor logger ios without metadata", "sensor logger ios standardised", "sensor logger ios with metadata zip",
            "sensor logger ios uncalibrated only",
        )
    }
}
