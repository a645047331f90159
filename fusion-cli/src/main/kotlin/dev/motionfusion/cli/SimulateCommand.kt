package dev.motionfusion.cli

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.io.AsciiNumbers
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.DeviceInfo
import dev.motionfusion.core.session.SensorInfo
import dev.motionfusion.core.session.SessionArchive
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionStream
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import java.io.BufferedOutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import java.util.Random
import java.util.zip.GZIPOutputStream

/** `fusion simulate -o OUT`: a session (or IMU table) from the project's MotionSimulator. */
internal class SimulateCommand(private val outputs: Outputs) : Command {
    override val name = "simulate"
    override val summary = "write a simulated recording with known truth (session or IMU table)"
    override val help = """
        |Usage: fusion simulate -o OUT [--duration S] [--rate HZ] [--seed N]
        |
        |Runs the project's MotionSimulator (seeded: the same options give the same data) and
        |writes what a phone would have recorded, values rounded to float like SensorEvent:
        |  OUT ending in .csv or .csv.gz: a plain IMU table t_s,gx,gy,gz,ax,ay,az,mx,my,mz
        |  OUT ending in .zip: a session zip; otherwise a session folder, with
        |    accelerometer, gyroscope, magnetometer (same instants), truth.csv (the true
        |    orientation) and rotation_vector.csv at a quarter of the rate: a stand-in for the
        |    phone's own fusion, the truth with a 2° heading offset and 0.3° noise.
        |
        |Motion: smooth random rotation (1 rad/s per axis), at rest for the first and last
        |2 s; gyroscope bias (0.01, −0.02, 0.015) rad/s; noise 0.002 rad/s, 0.03 m/s², 0.3 µT;
        |field 48 µT, dip 60°; timestamps with 0.2 ms jitter.
        |
        |Options:
        |  -o, --output OUT     required
        |  --duration S         seconds (default 20)
        |  --rate HZ            sample rate (default 100)
        |  --seed N             random seed (default 8)
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output", "--duration", "--rate", "--seed"), emptySet())
        if (o.positional.isNotEmpty()) throw UsageException("unexpected argument '${o.positional[0]}'")
        val output = o.value("-o") ?: o.value("--output") ?: throw UsageException("simulate needs -o OUT")
        val duration = o.double("--duration") ?: 20.0
        val rate = o.double("--rate") ?: 100.0
        val seed = o.long("--seed") ?: 8L
        if (duration <= 4.0 || duration > 86_400.0) throw UsageException("--duration must be in (4, 86400] s")
        if (rate < 10.0 || rate > 2000.0) throw UsageException("--rate must be in [10, 2000] Hz")
        val settings = try {
            settings(seed, rate, duration)
        } catch (e: IllegalArgumentException) {
            throw UsageException(e.message ?: "invalid simulation")
        }
        val simulator = MotionSimulator(settings)
        val path = Paths.get(output)
        val lower = output.lowercase()
        val command = "fusion simulate --duration ${fmt(duration)} --rate ${fmt(rate)} --seed $seed"
        when {
            lower.endsWith(".csv") || lower.endsWith(".csv.gz") -> writeTable(outputs.file(output, emptyList()), simulator, lower.endsWith(".gz"))
            lower.endsWith(".zip") -> {
                val zip = outputs.file(output, emptyList())
                val tmp = Files.createTempDirectory("fusion-simulate")
                val dir = tmp.resolve(path.fileName.toString().removeSuffix(".zip").removeSuffix(".ZIP"))
                try {
                    writeSession(dir, simulator, rate, seed, command)
                    zip.use { SessionArchive.zip(dir, it, entryTimeMs = START_WALL_CLOCK_MS) }
                } finally {
                    tmp.toFile().deleteRecursively()
                }
            }
            else -> {
                val dir = outputs.folder(output, emptyList())
                // Name the session the user asked for, not the folder it is written in aside.
                try {
                    writeSession(dir, simulator, rate, seed, command)
                } catch (e: java.io.IOException) {
                    throw java.nio.file.FileSystemException(output, null, dev.motionfusion.core.io.AtomicFiles.reason(e))
                }
            }
        }
        out.println("$output: $written samples, ${fmt(duration)} s at ${fmt(rate)} Hz ($command)")
        return ExitCode.OK
    }

    private companion object {
        /** The simulated recording's fixed wall-clock start (2025-11-26 12:00 UTC): reproducible output. */
        const val START_WALL_CLOCK_MS = 1_764_158_400_000L
    }

    private fun fmt(v: Double) = if (v == Math.rint(v)) v.toLong().toString() else v.toString()

    private fun settings(seed: Long, rate: Double, duration: Double) = SimulationSettings(
        seed = seed,
        rateHz = rate,
        durationS = duration,
        restWindows = listOf(TimeWindow(0.0, 2.0), TimeWindow(duration - 2.0, duration + 1.0)),
        gyroBias = Vector3(0.01, -0.02, 0.015),
        timestampJitter = minOf(0.0002, 0.2 / rate),
    )

    /** Samples written by the last run (the simulation streams to the output, never held in memory). */
    private var written = 0L

    private fun writeTable(file: java.io.OutputStream, simulator: MotionSimulator, gzip: Boolean) {
        val raw = BufferedOutputStream(file, 1 shl 16)
        val stream = if (gzip) GZIPOutputStream(raw, 1 shl 16) else raw
        stream.use { s ->
            s.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n".toByteArray())
            val buf = ByteArray(512)
            simulator.forEach { x ->
                written++
                var p = AsciiNumbers.fixed(buf, 0, x.timestampNs * 1e-9, 9)
                for (v in listOf(x.gyro, x.acc, x.mag)) {
                    for (k in 0 until 3) {
                        buf[p++] = ','.code.toByte()
                        p = AsciiNumbers.float(buf, p, v[k].toFloat())
                    }
                }
                buf[p++] = '\n'.code.toByte()
                s.write(buf, 0, p)
            }
        }
    }

    private fun writeSession(dir: Path, simulator: MotionSimulator, rate: Double, seed: Long, command: String) {
        val base = 1_000_000_000_000L // an elapsedRealtimeNanos-like origin (about 17 minutes after boot)
        val period = (1e6 / rate).toInt()
        val meta = SessionMetadata(
            appVersion = Cli.VERSION,
            source = command,
            device = DeviceInfo("Motion Fusion", "MotionSimulator", "", 0),
            startAnchor = ClockAnchor(START_WALL_CLOCK_MS, base),
            sensors = listOf(
                SensorInfo(SessionStream.ACCELEROMETER, "simulated accelerometer", "dev.motionfusion", 1, requestedPeriodUs = period),
                SensorInfo(SessionStream.GYROSCOPE, "simulated gyroscope", "dev.motionfusion", 1, requestedPeriodUs = period),
                SensorInfo(SessionStream.MAGNETOMETER, "simulated magnetometer", "dev.motionfusion", 1, requestedPeriodUs = period),
                SensorInfo(SessionStream.ROTATION_VECTOR, "simulated rotation vector (truth + 2° heading offset + 0.3° noise)", "dev.motionfusion", 1, requestedPeriodUs = 4 * period),
            ),
            filterSettings = null,
        )
        val random = Random(seed xor 0x5EED)
        val offset = Quaternion.fromAxisAngle(Vector3.UNIT_Z, Math.toRadians(2.0))
        SessionWriter.create(dir, meta).use { w ->
            var i = 0L
            simulator.forEach { s ->
                written++
                val t = base + s.timestampNs
                w.accelerometer(t, s.acc.x.toFloat(), s.acc.y.toFloat(), s.acc.z.toFloat(), 3)
                w.magnetometer(t, s.mag.x.toFloat(), s.mag.y.toFloat(), s.mag.z.toFloat(), 3)
                w.gyroscope(t, s.gyro.x.toFloat(), s.gyro.y.toFloat(), s.gyro.z.toFloat(), 3)
                w.truth(t, s.truth.w, s.truth.x, s.truth.y, s.truth.z)
                if (i++ % 4 == 0L) {
                    val noise = Vector3(random.nextGaussian(), random.nextGaussian(), random.nextGaussian()) * Math.toRadians(0.3)
                    val rv = (offset * s.truth * Quaternion.fromRotationVector(noise)).normalized().canonical()
                    w.rotationVector(t, rv.x.toFloat(), rv.y.toFloat(), rv.z.toFloat(), rv.w.toFloat(), Math.toRadians(5.0).toFloat(), 3)
                }
            }
        }
    }
}
