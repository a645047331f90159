package dev.motionfusion.core.io

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.IOException
import java.nio.file.FileSystemException
import java.nio.file.Files
import java.nio.file.Path

class AtomicFilesTest {
    @TempDir
    lateinit var dir: Path

    private fun listing() = Files.list(dir).use { s -> s.map { it.fileName.toString() }.sorted().toList() }

    @Test
    fun `a write replaces the file whole and leaves nothing beside it`() {
        val f = dir.resolve("a.txt")
        AtomicFiles().write(f, "one".toByteArray())
        AtomicFiles().write(f, "two".toByteArray())
        assertEquals("two", Files.readString(f))
        assertEquals(listOf("a.txt"), listing())
    }

    @Test
    fun `a failing writer leaves the previous file as it was`() {
        val f = dir.resolve("a.txt")
        Files.writeString(f, "previous")
        assertThrows(IllegalStateException::class.java) {
            AtomicFiles().write(f) { it.write("partial".toByteArray()); error("the producer failed") }
        }
        assertEquals("previous", Files.readString(f))
        assertEquals(listOf("a.txt"), listing())
    }

    @Test
    fun `a full disk fails naming the file and the reason, the previous file untouched`() {
        val f = dir.resolve("a.txt")
        Files.writeString(f, "previous")
        for (space in listOf(0L, 3L, 99L)) {
            val e = assertThrows(FileSystemException::class.java) {
                AtomicFiles(FaultyFiles(spaceBytes = space)).write(f, ByteArray(100) { 'x'.code.toByte() })
            }
            assertEquals(f.toAbsolutePath().toString(), e.file)
            assertEquals("No space left on device", e.reason)
            assertEquals("previous", Files.readString(f))
            assertEquals(listOf("a.txt"), listing())
        }
    }

    @Test
    fun `a kill at any step leaves the old or the new file, never a part`() {
        val f = dir.resolve("a.txt")
        val counter = FaultyFiles()
        Files.writeString(f, "old")
        AtomicFiles(counter).write(f, "new content".toByteArray())
        assertTrue(counter.steps >= 5, "create, write, sync, move, folder sync: ${counter.steps}")
        for (k in 0 until counter.steps) {
            Files.writeString(f, "old")
            val ops = FaultyFiles(killAt = k)
            assertThrows(SimulatedKill::class.java) { AtomicFiles(ops).write(f, "new content".toByteArray()) }
            ops.closeAll()
            val now = Files.readString(f)
            assertTrue(now == "old" || now == "new content", "kill at step $k: '$now'")
            Files.list(dir).use { s -> s.filter { it != f }.forEach(Files::delete) } // the temporary file a kill leaves
        }
    }

    @Test
    fun `a rename refuses an existing target`() {
        val a = Files.createDirectory(dir.resolve("a"))
        Files.createDirectory(dir.resolve("b"))
        assertThrows(IOException::class.java) { AtomicFiles().rename(a, dir.resolve("b")) }
        AtomicFiles().rename(a, dir.resolve("c"))
        assertEquals(listOf("b", "c"), listing())
    }
}
