package dev.motionfusion.core.session

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FaultyFiles
import dev.motionfusion.core.io.Json
import dev.motionfusion.core.io.SimulatedKill
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.IOException
import java.nio.file.Files
import java.nio.file.Path
import java.security.MessageDigest

/**
 * Kills and full disks at every write step of the writer and of recovery (through FaultyFiles),
 * and the harm recovery must never do: afterwards the session reads as complete or can be
 * recovered, and no row that reached the disk whole is lost.
 */
class SessionDurabilityTest {
    @TempDir
    lateinit var tmp: Path

    private val meta = SessionMetadata(appVersion = "test", startAnchor = ClockAnchor(1_764_000_000_000L, 1_000L))

    /** Timestamps of the rows the script hands to the writer, per stream. */
    private val script: Map<SessionStream, List<Long>> = run {
        val acc = ArrayList<Long>()
        val gyro = ArrayList<Long>()
        val mag = ArrayList<Long>()
        for (i in 0 until 120) {
            val t = 1_000L + i * 5_000_000L
            acc += t; gyro += t
            if (i % 3 == 0) mag += t
        }
        mapOf(SessionStream.ACCELEROMETER to acc, SessionStream.GYROSCOPE to gyro, SessionStream.MAGNETOMETER to mag)
    }

    /** A recording: rows on three streams, flushes, a pause, an anchor checkpoint, close. */
    private fun record(w: SessionWriter) {
        for (i in 0 until 120) {
            val t = 1_000L + i * 5_000_000L
            w.accelerometer(t, i.toFloat(), 0f, 9.81f, 3)
            w.gyroscope(t, i * 0.01f, 0f, 0f, 3)
            if (i % 3 == 0) w.magnetometer(t, 20f, 0f, -40f, 3)
            if (i == 30) w.flush()
            if (i == 50) w.pause(t)
            if (i == 60) w.resume(t)
            if (i == 80) w.anchor(ClockAnchor(1_764_000_000_400L, t))
            if (i == 100) w.flush()
        }
        w.close()
    }

    private fun timestamps(dir: Path, s: SessionStream): List<Long> = SessionReader.open(dir).use { r ->
        if (s !in r.streams) return emptyList()
        r.stream(s).use { e -> generateSequence { if (e.next()) e.timestampNs else null }.toList() }
    }

    /** Complete lines after the header: the rows that reached the file whole. */
    private fun wholeRows(f: Path): Int = if (!Files.exists(f)) 0 else maxOf(0, Files.readAllBytes(f).count { it == '\n'.code.toByte() } - 1)

    private val minBuffer = 4 * 400 // small buffers: many writes, many kill points

    @Test
    fun `a kill at every write step of the writer leaves a complete or recoverable session`() {
        val counter = FaultyFiles()
        SessionWriter.create(tmp.resolve("count"), meta, bufferBytes = minBuffer, files = counter).use(::record)
        val steps = counter.steps
        assertTrue(steps > 40, "kill points: $steps")
        var complete = 0
        var recovered = 0
        var nothing = 0
        for (k in 0 until steps) {
            val dir = tmp.resolve("w$k")
            val ops = FaultyFiles(killAt = k)
            assertThrows(SimulatedKill::class.java) { SessionWriter.create(dir, meta, bufferBytes = minBuffer, files = ops).use(::record) }
            ops.closeAll()
            val onDisk = script.keys.associateWith { wholeRows(dir.resolve(it.fileName)) }
            if (!Files.exists(dir.resolve(SessionMetadata.FILE_NAME))) {
                // Killed within the first metadata write, before any sample: nothing was recorded.
                assertTrue(onDisk.values.all { it == 0 }, "step $k")
                nothing++
                continue
            }
            val m = SessionReader.open(dir).use { it.metadata }
            if (m.complete) {
                complete++
            } else {
                assertTrue(SessionRecovery.isInterrupted(dir), "step $k")
                SessionRecovery.recover(dir)
                recovered++
            }
            for ((s, expected) in script) {
                val got = timestamps(dir, s)
                if (m.complete) assertEquals(expected, got, "step $k ${s.fileName}")
                else assertEquals(expected.take(onDisk.getValue(s)), got, "step $k ${s.fileName}: every whole row kept, in order")
            }
        }
        println("writer kill points: $steps ($complete complete, $recovered recovered, $nothing before the first sample)")
        assertTrue(complete > 0 && recovered > 0)
    }

    @Test
    fun `complete is written only after the streams are synced`() {
        val log = ArrayList<String>()
        val ops = object : dev.motionfusion.core.io.FileOperations by dev.motionfusion.core.io.FileOperations.SYSTEM {
            override fun create(path: Path) = logged(path, dev.motionfusion.core.io.FileOperations.SYSTEM.create(path))

            override fun open(path: Path) = logged(path, dev.motionfusion.core.io.FileOperations.SYSTEM.open(path))

            fun logged(path: Path, out: dev.motionfusion.core.io.SyncedOutput): dev.motionfusion.core.io.SyncedOutput {
                val name = path.fileName.toString()
                return object : dev.motionfusion.core.io.SyncedOutput() {
                    override fun write(b: Int) = out.write(b)
                    override fun write(b: ByteArray, off: Int, len: Int) = out.write(b, off, len)
                    override fun sync() { log += "sync $name"; out.sync() }
                    override fun close() = out.close()
                }
            }

            override fun move(source: Path, target: Path, replace: Boolean) {
                log += "move ${target.fileName}"
                dev.motionfusion.core.io.FileOperations.SYSTEM.move(source, target, replace)
            }

            override fun syncFolder(dir: Path) {
                log += "sync folder"
                dev.motionfusion.core.io.FileOperations.SYSTEM.syncFolder(dir)
            }
        }
        val w = SessionWriter.create(tmp.resolve("order"), meta, files = ops)
        w.gyroscope(1L, 0f, 0f, 0f, 3)
        w.accelerometer(1L, 0f, 0f, 9.8f, 3)
        log.clear()
        w.anchor(ClockAnchor(5L, 2L))
        assertEquals(listOf("sync accelerometer.csv", "sync gyroscope.csv", "sync .meta.json", "move meta.json", "sync folder"),
            log.map { it.replace(Regex("""\.meta\.json\.\w+\.tmp"""), ".meta.json") })
        log.clear()
        w.close()
        assertEquals(listOf("sync accelerometer.csv", "sync gyroscope.csv", "sync .meta.json", "move meta.json", "sync folder"),
            log.map { it.replace(Regex("""\.meta\.json\.\w+\.tmp"""), ".meta.json") })
    }

    @Test
    fun `a full disk while recording leaves a recoverable session with every row that reached it`() {
        // The smallest holds meta.json (with its frames) and little more: the disk fills at the first rows.
        for (space in listOf(800L, 3_000L, 9_000L)) {
            val dir = tmp.resolve("full$space")
            val ops = FaultyFiles(spaceBytes = space)
            val w = SessionWriter.create(dir, meta, bufferBytes = minBuffer, files = ops)
            val e = assertThrows(IOException::class.java) { record(w) }
            assertTrue(e.message!!.contains("No space left on device"), e.message)
            w.abandon()
            SessionRecovery.recover(dir)
            for (s in script.keys) {
                val got = timestamps(dir, s)
                assertEquals(script.getValue(s).take(got.size), got, "$space ${s.fileName}")
            }
        }
    }

    /** An interrupted session with partial rows, a file cut inside its header, a leftover temporary file and members of a newer version. */
    private fun interrupted(dir: Path): Path {
        val w = SessionWriter.create(dir, meta)
        for (i in 0 until 40) {
            w.accelerometer(1_000L + i * 10_000_000L, 0f, 0f, 9.81f, 3)
            w.gyroscope(1_000L + i * 10_000_000L, 0.01f, 0f, 0f, 3)
        }
        w.pause(400_000_000L)
        w.abandon()
        fun append(name: String, text: String) = Files.write(dir.resolve(name), text.toByteArray(), java.nio.file.StandardOpenOption.CREATE, java.nio.file.StandardOpenOption.APPEND)
        append("gyroscope.csv", "400001000,0.0")
        append("accelerometer.csv", "400001000,0,0,9.8")
        append("magnetometer.csv", "timestamp_ns,x_u")
        Files.writeString(dir.resolve(".meta.json.1234abcd.tmp"), "{\"format\": \"motion-")
        val json = Files.readString(dir.resolve("meta.json"))
            .replaceFirst("{\n", "{\n  \"future_member\": {\"kept\": [1, 2.5, \"x\"]},\n")
            .replace("\"sdk_int\": 0", "\"sdk_int\": 0,\n    \"board\": \"newer\"")
        Files.writeString(dir.resolve("meta.json"), json)
        return dir
    }

    private fun copy(from: Path, to: Path): Path {
        Files.createDirectories(to)
        Files.list(from).use { s -> s.forEach { Files.copy(it, to.resolve(it.fileName)) } }
        return to
    }

    private fun checkRecovered(dir: Path, label: String) {
        val m = SessionReader.open(dir).use { it.metadata }
        assertTrue(m.complete && m.recovered, label)
        assertEquals(40, timestamps(dir, SessionStream.GYROSCOPE).size, label)
        assertEquals(40, timestamps(dir, SessionStream.ACCELEROMETER).size, label)
        assertEquals("timestamp_ns,x_uT,y_uT,z_uT,accuracy\n", Files.readString(dir.resolve("magnetometer.csv")), label)
        val raw = Json.parse(Files.readString(dir.resolve("meta.json")), "meta.json") as Map<*, *>
        assertEquals(mapOf("kept" to listOf(1L, 2.5, "x")), raw["future_member"], label)
        assertEquals("newer", (raw["device"] as Map<*, *>)["board"], label)
        assertEquals(400_000_000L, m.pauses.single().endElapsedRealtimeNs, "the open pause is closed at the last sample: $label")
        assertFalse(Files.exists(dir.resolve(".meta.json.1234abcd.tmp")), label)
    }

    @Test
    fun `recovery keeps unknown members, restores a cut header and removes its own leftovers`() {
        val dir = interrupted(tmp.resolve("s"))
        val report = SessionRecovery.recover(dir)
        assertEquals(13L, report.truncatedBytes[SessionStream.GYROSCOPE])
        checkRecovered(dir, "one recovery")
        val again = SessionRecovery.recover(dir)
        assertTrue(again.wasComplete && !again.repaired)
    }

    @Test
    fun `a kill at every step of recovery leaves a session that recovery finishes`() {
        val template = interrupted(tmp.resolve("template"))
        val counter = FaultyFiles()
        SessionRecovery(counter).recover(copy(template, tmp.resolve("count")), dryRun = false)
        val steps = counter.steps
        assertTrue(steps >= 10, "kill points: $steps")
        for (k in 0 until steps) {
            val dir = copy(template, tmp.resolve("r$k"))
            val ops = FaultyFiles(killAt = k)
            assertThrows(SimulatedKill::class.java) { SessionRecovery(ops).recover(dir, dryRun = false) }
            ops.closeAll()
            val m = SessionReader.open(dir).use { it.metadata }
            assertTrue(m.complete || SessionRecovery.isInterrupted(dir), "step $k")
            SessionRecovery.recover(dir)
            checkRecovered(dir, "kill at step $k")
        }
        println("recovery kill points: $steps")
    }

    @Test
    fun `a full disk during recovery changes nothing that matters and names the file`() {
        val template = interrupted(tmp.resolve("template"))
        for (space in listOf(0L, 10L, 500L)) {
            val dir = copy(template, tmp.resolve("full$space"))
            val e = assertThrows(IOException::class.java) { SessionRecovery(FaultyFiles(spaceBytes = space)).recover(dir, dryRun = false) }
            assertTrue(e.message!!.contains("No space left on device"), e.message)
            assertTrue(SessionRecovery.isInterrupted(dir), "still interrupted and readable")
            SessionRecovery.recover(dir)
            checkRecovered(dir, "after a full disk ($space bytes)")
        }
    }

    private fun hashes(root: Path): Map<String, String> {
        val md = MessageDigest.getInstance("SHA-256")
        return Files.walk(root).use { s ->
            s.filter { it != root }.toList().associate { p ->
                val rel = root.relativize(p).toString()
                rel to when {
                    Files.isSymbolicLink(p) -> "link → " + Files.readSymbolicLink(p)
                    Files.isDirectory(p) -> "folder"
                    else -> md.digest(Files.readAllBytes(p)).joinToString("") { "%02x".format(it) }
                }
            }
        }
    }

    @Test
    fun `a dry run changes nothing and says what recovery would do`() {
        val dir = interrupted(tmp.resolve("s"))
        val before = hashes(tmp)
        val report = SessionRecovery().recover(dir, dryRun = true)
        assertEquals(before, hashes(tmp))
        assertTrue(report.dryRun && report.actions.any { it.startsWith("gyroscope.csv: cut 13 bytes") }, report.actions.toString())
        assertTrue(report.actions.any { it.startsWith("magnetometer.csv: cut inside its header") }, report.actions.toString())
    }

    @Test
    fun `recovery refuses foreign folders, links and malformed rows, and changes nothing`() {
        val outside = Files.createDirectories(tmp.resolve("outside"))
        Files.writeString(outside.resolve("precious.csv"), "timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0,0,3\n2,0,0")

        // A foreign project's folder: a meta.json with a format_version but not this project's marker.
        val foreign = Files.createDirectories(tmp.resolve("foreign"))
        Files.writeString(foreign.resolve("meta.json"), "{\"format_version\": 1, \"complete\": false, \"theirs\": 1}")
        Files.writeString(foreign.resolve("gyroscope.csv"), "timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0,0,3\n2,0")

        // A session whose stream is a link to a file outside it.
        val linked = interrupted(tmp.resolve("linked"))
        Files.delete(linked.resolve("gyroscope.csv"))
        Files.createSymbolicLink(linked.resolve("gyroscope.csv"), outside.resolve("precious.csv"))

        // A session with a malformed row in the middle of one stream, after a good stream that needs a cut.
        val bad = interrupted(tmp.resolve("bad"))
        val g = bad.resolve("gyroscope.csv")
        Files.writeString(g, Files.readString(g).replaceFirst("\n50001000,", "\n50001000,zz"))

        // A folder without meta.json holding other files.
        val other = Files.createDirectories(tmp.resolve("other"))
        Files.writeString(other.resolve("gyroscope.csv"), "timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0,0,3\n")
        Files.writeString(other.resolve("notes.txt"), "mine")

        val before = hashes(tmp)
        for ((dir, pattern) in listOf(
            foreign to "not a Motion Fusion session",
            linked to "gyroscope.csv: is a symbolic link",
            bad to "gyroscope.csv:7:",
            other to "holds other files (notes.txt)",
        )) {
            val e = assertThrows(DataFormatException::class.java) { SessionRecovery.recover(dir) }
            assertTrue(e.message!!.contains(pattern), e.message)
            assertFalse(SessionRecovery.isInterrupted(dir))
        }
        assertEquals(before, hashes(tmp), "nothing changed anywhere")
    }

    @Test
    fun `an unreadable meta json is rebuilt from the streams and kept aside`() {
        val dir = interrupted(tmp.resolve("s"))
        val meta = dir.resolve("meta.json")
        val original = Files.readAllBytes(meta).copyOf(40) // what an in-place write on a full disk left
        Files.write(meta, original)
        assertThrows(DataFormatException::class.java) { SessionReader.open(dir).close() }
        assertTrue(SessionRecovery.isInterrupted(dir))
        val report = SessionRecovery.recover(dir)
        assertTrue(report.rebuiltMetadata)
        assertTrue(original.contentEquals(Files.readAllBytes(dir.resolve(SessionRecovery.UNREADABLE_META))))
        val m = SessionReader.open(dir).use { it.metadata }
        assertTrue(m.complete && m.recovered)
        assertEquals(40L, m.streams.getValue(SessionStream.GYROSCOPE).samples)
        assertEquals(40, timestamps(dir, SessionStream.ACCELEROMETER).size)
    }

    @Test
    fun `stream statistics cannot overflow on extreme timestamps`() {
        val acc = StatsAccumulator()
        for (t in longArrayOf(Long.MIN_VALUE, Long.MAX_VALUE, Long.MIN_VALUE, 0L, 1_000_000L)) acc.add(t)
        val st = acc.result()
        assertEquals(5L, st.samples)
        assertEquals(1L, st.backwards)
        assertEquals(1000.0, st.achievedRateHz, 1e-9, "only the 1 ms interval counts")
        assertEquals(1.0, ClockAnchor(0L, Long.MIN_VALUE).toWallClockMs(Long.MAX_VALUE) / (Long.MAX_VALUE.toDouble() * 2 / 1e6), 1e-12)
    }
}
