package dev.motionfusion.stream

import dev.motionfusion.core.PublicApi
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File

/**
 * The public API of fusion-stream, listed from the compiled main classes as fusion-core's
 * (PublicApiTest, whose lister this reuses) and compared with the committed `api/fusion-stream.api`.
 * After an intended change, regenerate it with
 *
 *     mvn -B -pl fusion-core,fusion-stream test -Dtest=StreamApiTest -Dsurefire.failIfNoSpecifiedTests=false -Dapi.update=true
 */
class StreamApiTest {
    private val classes = PublicApi.classesOf("dev/motionfusion/stream")

    @Test
    fun `the public API equals the committed listing`() {
        PublicApi.check(classes, File("api/fusion-stream.api"), "fusion-stream")
    }

    @Test
    fun `the listing holds the server and client but not their internals`() {
        val text = PublicApi.listing(classes)
        assertTrue("class dev.motionfusion.stream.StreamServer " in text, "a public class is listed")
        assertTrue("closeUnpaired" !in text, "an internal function is not listed")
        assertTrue("HELLO_PART_BYTES" !in text, "an internal constant is not listed")
    }
}
