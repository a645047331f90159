package dev.motionfusion.core.session

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.DataFormatException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.ByteArrayOutputStream
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path

/** markers.csv: written by the one session writer, read as its own optional stream, listed in meta.json, kept by recovery and the zip. */
class SessionMarkersTest {
    @TempDir
    lateinit var tmp: Path

    private val meta = SessionMetadata(appVersion = "0.1.0", startAnchor = ClockAnchor(1_764_000_000_000L, 5_000_000_000L))

    private fun session(name: String, vararg markers: Pair<Long, String>): Path {
        val dir = tmp.resolve(name)
        SessionWriter.create(dir, meta).use { w ->
            w.gyroscope(5_000_000_000L, 0.1f, 0.2f, 0.3f, 3)
            for ((t, label) in markers) w.marker(t, label)
            w.gyroscope(9_000_000_000L, 0.1f, 0.2f, 0.3f, 3)
        }
        return dir
    }

    @Test
    fun `markers round-trip through writer and reader, and meta json lists them with the streams`() {
        val dir = session("s", 6_000_000_000L to "start walking", 7_500_000_000L to "", 8_000_000_000L to "stairs")
        SessionReader.open(dir).use { r ->
            assertTrue(r.hasMarkers)
            assertEquals(
                listOf(Marker(6_000_000_000L, "start walking"), Marker(7_500_000_000L, ""), Marker(8_000_000_000L, "stairs")),
                r.markers(),
            )
            assertEquals(StreamStats(3, 6_000_000_000L, 8_000_000_000L, r.metadata.markers!!.achievedRateHz, r.metadata.markers!!.intervalStdMs, 0, 0), r.metadata.markers)
            // Markers are not sensor events: the replay's streams do not include them.
            assertEquals(setOf(SessionStream.GYROSCOPE), r.streams)
        }
        val json = String(Files.readAllBytes(dir.resolve("meta.json")), StandardCharsets.UTF_8)
        val listed = ((dev.motionfusion.core.io.Json.parse(json, "meta.json") as Map<*, *>)["streams"] as Map<*, *>)["markers"] as Map<*, *>
        assertEquals("markers.csv", listed["file"])
        assertEquals(3L, (listed["samples"] as Number).toLong())
        assertEquals(
            "timestamp_ns,label\n6000000000,\"start walking\"\n7500000000,\"\"\n8000000000,\"stairs\"\n",
            String(Files.readAllBytes(dir.resolve("markers.csv")), StandardCharsets.UTF_8),
        )
    }

    @Test
    fun `a session without markers has no markers file and reads an empty list`() {
        val dir = session("none")
        assertFalse(Files.exists(dir.resolve(SessionMarkers.FILE_NAME)))
        SessionReader.open(dir).use { r ->
            assertFalse(r.hasMarkers)
            assertEquals(emptyList<Marker>(), r.markers())
            assertEquals(null, r.metadata.markers)
        }
    }

    @Test
    fun `hostile labels are stored as one line, quoted, and read back as stored`() {
        val tenKb = "x".repeat(10_000)
        val labels = listOf(
            "two\nlines\r\nand\ttab",
            "a, b, c",
            "say \"hi\", \"\"quoted\"\"",
            "\"",
            tenKb,
            "emoji 😀 at the end".padStart(SessionMarkers.MAX_LABEL_CHARS - 1, '-') + "😀",
            "lone \uD800 surrogate",
            "  spaces around  ",
            "\u0000nul\u007fdel\u2028sep",
        )
        val dir = session("hostile", *labels.mapIndexed { i, l -> 6_000_000_000L + i to l }.toTypedArray())
        val read = SessionReader.open(dir).use { it.markers() }
        assertEquals(labels.size, read.size)
        assertEquals("two lines  and tab", read[0].label)
        assertEquals("a, b, c", read[1].label)
        assertEquals("say \"hi\", \"\"quoted\"\"", read[2].label)
        assertEquals("\"", read[3].label)
        assertEquals("x".repeat(SessionMarkers.MAX_LABEL_CHARS), read[4].label)
        // Cut before a surrogate pair rather than through it.
        assertTrue(read[5].label.length <= SessionMarkers.MAX_LABEL_CHARS && !Character.isHighSurrogate(read[5].label.last()), read[5].label)
        assertEquals("lone \uFFFD surrogate", read[6].label)
        assertEquals("spaces around", read[7].label)
        assertEquals("nul del sep", read[8].label)
        for ((i, m) in read.withIndex()) {
            assertEquals(6_000_000_000L + i, m.timestampNs)
            assertEquals(SessionMarkers.label(labels[i]), m.label)
            assertEquals(m.label, SessionMarkers.label(m.label), "stored form is stable")
        }
        // One header and one line per marker, whatever the labels held.
        assertEquals(labels.size + 1, Files.readAllLines(dir.resolve("markers.csv")).size)
    }

    private fun withMarkersFile(name: String, bytes: ByteArray): Path {
        val dir = session(name)
        Files.write(dir.resolve(SessionMarkers.FILE_NAME), bytes)
        return dir
    }

    private fun error(dir: Path): DataFormatException =
        assertThrows(DataFormatException::class.java) { SessionReader.open(dir).use { it.markers() } }

    @Test
    fun `malformed markers files fail at their line and column`() {
        val notUtf8 = "timestamp_ns,label\n6000000000,\"ok\"\n6100000000,\"caf".toByteArray() + byteArrayOf(0xC3.toByte(), 0x28) + "\"\n".toByteArray()
        val e1 = error(withMarkersFile("utf8", notUtf8))
        assertTrue(e1.message!!.contains("markers.csv:3:13") && e1.message!!.contains("not UTF-8"), e1.message)

        val e2 = error(withMarkersFile("time", "timestamp_ns,label\n6.5e9,\"x\"\n".toByteArray()))
        assertTrue(e2.message!!.contains("markers.csv:2:1") && e2.message!!.contains("timestamp_ns"), e2.message)

        val e3 = error(withMarkersFile("fields", "timestamp_ns,label\n6000000000,a,b\n".toByteArray()))
        assertTrue(e3.message!!.contains("markers.csv:2:") && e3.message!!.contains("3 fields"), e3.message)

        val long = "timestamp_ns,label\n6000000000,\"${"y".repeat(SessionMarkers.MAX_LABEL_CHARS + 1)}\"\n"
        val e4 = error(withMarkersFile("long", long.toByteArray()))
        assertTrue(e4.message!!.contains("markers.csv:2:13") && e4.message!!.contains("longer than"), e4.message)

        val e5 = error(withMarkersFile("header", "t,text\n1,a\n".toByteArray()))
        assertTrue(e5.message!!.contains("markers.csv:1:1") && e5.message!!.contains("timestamp_ns"), e5.message)
    }

    @Test
    fun `an unquoted label written by another tool is read too`() {
        val dir = withMarkersFile("pandas", "timestamp_ns,label\n6000000000,stairs\n6100000000,\n".toByteArray())
        assertEquals(listOf(Marker(6_000_000_000L, "stairs"), Marker(6_100_000_000L, "")), SessionReader.open(dir).use { it.markers() })
    }

    @Test
    fun `recovery cuts a partial marker row, counts the markers and keeps the file`() {
        val dir = tmp.resolve("killed")
        val w = SessionWriter.create(dir, meta)
        w.gyroscope(5_000_000_000L, 0.1f, 0.2f, 0.3f, 3)
        w.marker(6_000_000_000L, "kept, \"whole\"")
        w.flush()
        w.abandon()
        Files.write(dir.resolve("markers.csv"), "7000000000,\"cut of".toByteArray(), java.nio.file.StandardOpenOption.APPEND)
        // Unrecovered, the cut row is skipped as an interruption.
        assertEquals(listOf(Marker(6_000_000_000L, "kept, \"whole\"")), SessionReader.open(dir).use { it.markers() })
        val report = SessionRecovery.recover(dir)
        assertTrue(report.repaired)
        assertEquals(18L, report.markersTruncatedBytes)
        assertTrue(report.actions.any { it.startsWith("markers.csv: cut 18 bytes") }, report.actions.toString())
        SessionReader.open(dir).use { r ->
            assertTrue(r.metadata.recovered)
            assertEquals(1L, r.metadata.markers!!.samples)
            assertEquals(listOf(Marker(6_000_000_000L, "kept, \"whole\"")), r.markers())
        }
    }

    @Test
    fun `a malformed marker row stops recovery with nothing changed`() {
        val dir = tmp.resolve("bad")
        val w = SessionWriter.create(dir, meta)
        w.gyroscope(5_000_000_000L, 0.1f, 0.2f, 0.3f, 3)
        w.flush()
        w.abandon()
        Files.write(dir.resolve("markers.csv"), "timestamp_ns,label\nsoon,\"x\"\n".toByteArray())
        val before = Files.readAllBytes(dir.resolve("meta.json"))
        val e = assertThrows(DataFormatException::class.java) { SessionRecovery.recover(dir) }
        assertTrue(e.message!!.contains("markers.csv:2:1"), e.message)
        assertTrue(before.contentEquals(Files.readAllBytes(dir.resolve("meta.json"))))
    }

    @Test
    fun `the zip export carries the markers`() {
        val dir = session("zipped", 6_000_000_000L to "here")
        val zip = tmp.resolve("zipped.zip")
        SessionArchive.zip(dir, zip)
        SessionReader.open(zip).use { assertEquals(listOf(Marker(6_000_000_000L, "here")), it.markers()) }
        val bytes = ByteArrayOutputStream().also { SessionArchive.zip(dir, it) }.toByteArray()
        assertTrue(String(bytes, StandardCharsets.ISO_8859_1).contains("zipped/markers.csv"))
    }
}
