// fusion-stream: the live stream's WebSocket server (on the phone) and client (fusion listen) (fusion-stream/pom.xml).
plugins {
    alias(libs.plugins.kotlin.jvm)
}

kotlin {
    jvmToolchain(17)
    // As -Xexplicit-api=strict in fusion-stream/pom.xml (main sources only).
    explicitApi()
    compilerOptions {
        freeCompilerArgs.add("-Xjsr305=strict")
    }
}

// StreamApiTest lists the API with fusion-core's PublicApi: fusion-core's test classes on the test class path
// (Maven: fusion-core's test-jar, scope test).
evaluationDependsOn(":fusion-core")

sourceSets {
    main { kotlin.srcDirs("src/main/kotlin") }
    test {
        kotlin.srcDirs("src/test/kotlin")
        val coreTests = project(":fusion-core").the<SourceSetContainer>()["test"].output
        compileClasspath += coreTests
        runtimeClasspath += coreTests
    }
}

dependencies {
    implementation(project(":fusion-core"))
    implementation(libs.kotlin.stdlib)
    implementation(libs.java.websocket)
    // As the root pom's dependencyManagement: Java-WebSocket asks for an older slf4j-api, the build takes
    // the version of the slf4j provider (the app's APK and fusion listen carry the same one as Maven's).
    constraints {
        implementation(libs.slf4j.api)
    }
    testImplementation(platform(libs.junit.bom))
    testImplementation(libs.junit.jupiter)
    testImplementation(libs.slf4j.nop)
    // As fusion-core's test-jar in pom.xml; its test classes are added to the test source set above.
    testImplementation(project(":fusion-core"))
    testRuntimeOnly(libs.junit.platform.launcher)
}

tasks.test {
    useJUnitPlatform()
    maxHeapSize = "2g"
    // StreamApiTest lists the API from the compiled main classes (Maven: target/classes).
    systemProperty("api.classes", sourceSets.main.get().output.classesDirs.asPath)
}
